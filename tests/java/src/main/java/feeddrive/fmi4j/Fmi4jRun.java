package feeddrive.fmi4j;

import java.io.File;
import java.io.FileWriter;
import java.io.IOException;
import java.io.PrintWriter;
import java.util.Locale;

import no.ntnu.ihb.fmi4j.FmiStatus;
import no.ntnu.ihb.fmi4j.importer.fmi2.CoSimulationSlave;
import no.ntnu.ihb.fmi4j.importer.fmi2.Fmu;
import no.ntnu.ihb.fmi4j.importer.fmi2.ModelExchangeInstance;
import no.ntnu.ihb.fmi4j.modeldescription.variables.ModelVariables;

/**
 * Runs the feed-drive FMU in FMI4j, co-simulation and model exchange, for the open-loop input
 * u(t_k) = 0.5 sin(2 pi t_k) V held over each 0.5 ms sample, 2 s from rest at x = 0.15 m, and
 * writes time, u, x, v, F_friction, i per sample to cs.csv and me.csv.
 *
 * Co-simulation: one fmi2DoStep of 0.5 ms per sample. Model exchange: FMI4j provides the ME
 * API only, so this class integrates: classical Runge-Kutta 4 with a fixed 10 µs step, the time
 * event of every current-loop sample (inputs set first, then event mode), and state events located
 * by bisection on the Runge-Kutta step to 1e-12 s (crossing as the FMU defines it: g from > 0 to
 * <= 0 or from < 0 to >= 0).
 *
 * Usage: Fmi4jRun FMU OUT_DIR [seconds=2]. Prints the FMI4j version line and one summary line per
 * interface.
 */
public final class Fmi4jRun {
    static final double TS = 5e-4, X0 = 0.15, AMP = 0.5, FREQ = 1.0, H = 1e-5;
    static final String[] OUT = {"x", "v", "F_friction", "i"};

    static double input(long k) {
        return AMP * Math.sin(2 * Math.PI * FREQ * k * TS);
    }

    static void check(boolean ok, String what) {
        if (!ok) throw new IllegalStateException(what + " failed");
    }

    static void check(FmiStatus st, String what) {
        if (st != FmiStatus.OK && st != FmiStatus.Warning) throw new IllegalStateException(what + ": " + st);
    }

    public static void main(String[] args) throws Exception {
        File fmuFile = new File(args[0]);
        File outDir = new File(args[1]);
        double seconds = args.length > 2 ? Double.parseDouble(args[2]) : 2.0;
        long n = Math.round(seconds / TS);
        outDir.mkdirs();
        Package pkg = Fmu.class.getPackage();
        System.out.println("FMI4j fmi-import " + (pkg.getImplementationVersion() != null ? pkg.getImplementationVersion() : "(see pom)"));
        try (Fmu fmu = Fmu.from(fmuFile)) {
            ModelVariables mv = fmu.getModelDescription().getModelVariables();
            long[] outVr = mv.getValueReferences(OUT);
            long uVr = mv.getValueReference("u");
            long[] startVr = {mv.getValueReference("x"), mv.getValueReference("v"), uVr};
            runCs(fmu, n, outVr, uVr, startVr, new File(outDir, "cs.csv"));
            runMe(fmu, n, outVr, uVr, startVr, new File(outDir, "me.csv"));
        }
    }

    static PrintWriter csv(File f) throws IOException {
        PrintWriter w = new PrintWriter(new FileWriter(f));
        w.println("time,u,x,v,F_friction,i");
        return w;
    }

    static void row(PrintWriter w, double t, double u, double[] out) {
        w.println(String.format(Locale.ROOT, "%.17g,%.17g,%.17g,%.17g,%.17g,%.17g", t, u, out[0], out[1], out[2], out[3]));
    }

    static void runCs(Fmu fmu, long n, long[] outVr, long uVr, long[] startVr, File file) throws IOException {
        long t0 = System.nanoTime();
        CoSimulationSlave s = fmu.asCoSimulationFmu().newInstance("fmi4j_cs");
        double[] out = new double[outVr.length];
        try (PrintWriter w = csv(file)) {
            check(s.setupExperiment(0.0, 0.0, 1e-6), "setupExperiment");
            check(s.writeReal(startVr, new double[]{X0, 0.0, input(0)}), "start values");
            check(s.enterInitializationMode(), "enterInitializationMode");
            check(s.exitInitializationMode(), "exitInitializationMode");
            check(s.readReal(outVr, out), "readReal");
            row(w, 0.0, input(0), out);
            for (long k = 0; k < n; k++) {
                if (k > 0) check(s.writeReal(new long[]{uVr}, new double[]{input(k)}), "writeReal u");
                check(s.doStep(k * TS, TS), "doStep at " + k * TS);
                check(s.readReal(outVr, out), "readReal");
                row(w, (k + 1) * TS, input(k), out);
            }
            s.terminate();
        } finally {
            s.close();
        }
        System.out.printf(Locale.ROOT, "cs: %d steps in %.3f s%n", n, (System.nanoTime() - t0) * 1e-9);
    }

    /* ---- model exchange ---- */

    static final class Me {
        final ModelExchangeInstance m;
        final int nx, nz;
        long nEvents;

        Me(ModelExchangeInstance m, int nx, int nz) {
            this.m = m;
            this.nx = nx;
            this.nz = nz;
        }

        double[] deriv(double t, double[] x) {
            double[] dx = new double[nx];
            check(m.setTime(t), "setTime");
            check(m.setContinuousStates(x), "setContinuousStates");
            check(m.getDerivatives(dx), "getDerivatives");
            return dx;
        }

        double[] indicators(double t, double[] x) {
            double[] z = new double[nz];
            check(m.setTime(t), "setTime");
            check(m.setContinuousStates(x), "setContinuousStates");
            check(m.getEventIndicators(z), "getEventIndicators");
            return z;
        }

        double[] rk4(double t, double[] x, double h) {
            double[] k1 = deriv(t, x), y = new double[nx];
            for (int j = 0; j < nx; j++) y[j] = x[j] + 0.5 * h * k1[j];
            double[] k2 = deriv(t + 0.5 * h, y);
            for (int j = 0; j < nx; j++) y[j] = x[j] + 0.5 * h * k2[j];
            double[] k3 = deriv(t + 0.5 * h, y);
            for (int j = 0; j < nx; j++) y[j] = x[j] + h * k3[j];
            double[] k4 = deriv(t + h, y);
            double[] r = new double[nx];
            for (int j = 0; j < nx; j++) r[j] = x[j] + h / 6.0 * (k1[j] + 2 * k2[j] + 2 * k3[j] + k4[j]);
            return r;
        }

        static boolean crossed(double[] g0, double[] g1) {
            for (int j = 0; j < g0.length; j++)
                if ((g0[j] > 0 && g1[j] <= 0) || (g0[j] < 0 && g1[j] >= 0)) return true;
            return false;
        }

        void eventIteration() {
            check(m.enterEventMode(), "enterEventMode");
            check(m.newDiscreteStates(), "newDiscreteStates");
            check(m.enterContinuousTimeMode(), "enterContinuousTimeMode");
        }

        /** integrate from t to tEnd handling state events; returns the states at tEnd */
        double[] advance(double t, double tEnd, double[] x) {
            double[] g = indicators(t, x);
            while (t < tEnd - 1e-15) {
                double h = Math.min(H, tEnd - t);
                double[] x1 = rk4(t, x, h);
                double[] g1 = indicators(t + h, x1);
                if (!crossed(g, g1)) {
                    t += h;
                    x = x1;
                    g = g1;
                    continue;
                }
                /* bisection on the step length: largest tau with no crossing, smallest with */
                double lo = 0.0, hi = h;
                double[] xHi = x1;
                while (hi - lo > 1e-12) {
                    double mid = 0.5 * (lo + hi);
                    double[] xm = rk4(t, x, mid);
                    if (crossed(g, indicators(t + mid, xm))) {
                        hi = mid;
                        xHi = xm;
                    } else {
                        lo = mid;
                    }
                }
                t += hi;
                check(m.setTime(t), "setTime");
                check(m.setContinuousStates(xHi), "setContinuousStates");
                eventIteration();
                nEvents++;
                x = new double[nx];
                check(m.getContinuousStates(x), "getContinuousStates");
                g = indicators(t, x);
            }
            return x;
        }
    }

    static void runMe(Fmu fmu, long n, long[] outVr, long uVr, long[] startVr, File file) throws IOException {
        long t0 = System.nanoTime();
        ModelExchangeInstance inst = fmu.asModelExchangeFmu().newInstance("fmi4j_me");
        int nx = (int) fmu.getModelDescription().asModelExchangeModelDescription().getNumberOfContinuousStates();
        int nz = (int) fmu.getModelDescription().asModelExchangeModelDescription().getNumberOfEventIndicators();
        Me me = new Me(inst, nx, nz);
        double[] out = new double[outVr.length];
        try (PrintWriter w = csv(file)) {
            check(inst.setupExperiment(0.0, 0.0, 1e-6), "setupExperiment");
            check(inst.writeReal(startVr, new double[]{X0, 0.0, input(0)}), "start values");
            check(inst.enterInitializationMode(), "enterInitializationMode");
            check(inst.exitInitializationMode(), "exitInitializationMode");
            check(inst.newDiscreteStates(), "newDiscreteStates");
            check(inst.enterContinuousTimeMode(), "enterContinuousTimeMode");
            double[] x = new double[nx];
            check(inst.getContinuousStates(x), "getContinuousStates");
            check(inst.readReal(outVr, out), "readReal");
            row(w, 0.0, input(0), out);
            for (long k = 0; k < n; k++) {
                double t = k * TS;
                if (k > 0) {
                    /* the sample at t_k: input first, then the time event */
                    check(inst.writeReal(new long[]{uVr}, new double[]{input(k)}), "writeReal u");
                    me.eventIteration();
                    check(inst.getContinuousStates(x), "getContinuousStates");
                }
                x = me.advance(t, (k + 1) * TS, x);
                check(inst.setTime((k + 1) * TS), "setTime");
                check(inst.setContinuousStates(x), "setContinuousStates");
                check(inst.readReal(outVr, out), "readReal");
                row(w, (k + 1) * TS, input(k), out);
            }
            inst.terminate();
        } finally {
            inst.close();
        }
        System.out.printf(Locale.ROOT, "me: %d samples, %d state events in %.3f s%n", n, me.nEvents,
                (System.nanoTime() - t0) * 1e-9);
    }
}
