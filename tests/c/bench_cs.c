/* Benchmark of co-simulation from C on the paper's 30 mm / 6 s closed-loop sinusoid (2 kHz PID,
 * 100 nm scale, one 0.5 ms fmi2DoStep per controller sample):
 *   real-time factor  = simulated seconds / wall seconds of the whole loop (controller included),
 *   events            = friction state events (and current-loop time events) per simulated and per
 *                       wall-clock second,
 *   fmi2DoStep cost   = wall time of each 0.5 ms step: median, 99th percentile, maximum,
 *   wall floor        = the loop cut into chunks of CHUNK samples, each chunk's fastest wall time over
 *                       the repetitions, summed: the loop's time with the preemptions of a loaded
 *                       machine filtered out (a chunk of 25 us is rarely interrupted in every one).
 * Each repetition runs the loop twice: once timed as a whole (wall, floor: no clock read inside a
 * sample, no check of the tracking error), once with a clock read around every fmi2DoStep (its
 * quantiles, the tracking error, the counters).
 * Usage: bench_cs LinearMotorFeedDrive.so [repetitions [fast|adaptive]] (solver.fast on / off; default:
 * the FMU's). Prints one JSON object. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cs_loop.h"
#include "model_vars.h"

#define N_SAMPLES 12000L    /* 6 s at 2 kHz */
#define CHUNK 50L           /* samples per chunk of the wall floor */

static int cmp_double(const void *a, const void *b) {
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

static double quantile(const double *sorted, long n, double q) {
    double pos = q * (double)(n - 1);
    long i = (long)pos;
    double f = pos - (double)i;
    return i + 1 < n ? sorted[i] * (1.0 - f) + sorted[i + 1] * f : sorted[n - 1];
}

int main(int argc, char **argv) {
    fmi_api_t api;
    char err[512];
    int reps = argc > 2 ? atoi(argv[2]) : 5, r;
    int fast = argc > 3 ? (strcmp(argv[3], "fast") == 0 ? 1 : (strcmp(argv[3], "adaptive") == 0 ? 0 : -2)) : -1;
    double best_wall = 1e300, sum_wall = 0.0, *walls;
    long n_state = 0, n_time = 0, n_steps = 0, n_rhs = 0, total = 0;
    double max_err = 0.0, chunk_best[N_SAMPLES / CHUNK], wall_floor = 0.0;
    if (fmi_api_load(&api, argc > 1 ? argv[1] : NULL, err, sizeof err) != 0) {
        fprintf(stderr, "%s\n", err);
        return 2;
    }
    if (reps < 1) reps = 1;
    if (fast == -2) {
        fprintf(stderr, "bench_cs: solver %s: allowed fast or adaptive\n", argv[3]);
        return 2;
    }
    walls = (double *)malloc(sizeof(double) * (size_t)(N_SAMPLES * reps));
    for (r = 0; r < (int)(N_SAMPLES / CHUNK); r++) chunk_best[r] = 1e300;
    for (r = 0; r < reps; r++) {
        cs_loop_t L;
        cs_sample_t s;
        long k;
        double w0, w, c0;
        /* the loop timed as a whole */
        if (cs_loop_open_with(&L, &api, "bench", NULL, 0.0, 1, fast) != 0) return 1;
        w0 = c0 = host_now();
        for (k = 0; k < N_SAMPLES; k++) {
            if (k > 0 && k % CHUNK == 0) {
                double c1 = host_now();
                if (c1 - c0 < chunk_best[k / CHUNK - 1]) chunk_best[k / CHUNK - 1] = c1 - c0;
                c0 = c1;
            }
            if (cs_loop_step(&L, &s) > fmi2Warning) { fprintf(stderr, "step %ld failed: %s\n", k, L.env.last); return 1; }
        }
        w = host_now();
        if (w - c0 < chunk_best[N_SAMPLES / CHUNK - 1]) chunk_best[N_SAMPLES / CHUNK - 1] = w - c0;
        w -= w0;
        sum_wall += w;
        if (w < best_wall) best_wall = w;
        cs_loop_close(&L);
        /* every fmi2DoStep timed, the tracking error checked */
        if (cs_loop_open_with(&L, &api, "bench", NULL, 0.0, 1, fast) != 0) return 1;
        L.dostep_wall = walls + total;
        L.cap_dostep = N_SAMPLES;
        for (k = 0; k < N_SAMPLES; k++) {
            double e;
            if (cs_loop_step(&L, &s) > fmi2Warning) { fprintf(stderr, "step %ld failed: %s\n", k, L.env.last); return 1; }
            e = s.x - pid_reference(&L.ctrl, L.t);
            if (e < 0) e = -e;
            if (e > max_err) max_err = e;
        }
        total += L.n_dostep;
        n_state = cs_loop_stat(&L, VR_stats_n_state_events);
        n_time = cs_loop_stat(&L, VR_stats_n_time_events);
        n_steps = cs_loop_stat(&L, VR_stats_n_steps);
        n_rhs = cs_loop_stat(&L, VR_stats_n_rhs);
        cs_loop_close(&L);
    }
    qsort(walls, (size_t)total, sizeof(double), cmp_double);
    for (r = 0; r < (int)(N_SAMPLES / CHUNK); r++) wall_floor += chunk_best[r];
    {
        double sim = N_SAMPLES * 5e-4, mean_wall = sum_wall / reps;
        printf("{\"simulated_s\": %.6g, \"repetitions\": %d, \"wall_s_best\": %.6g, \"wall_s_mean\": %.6g, "
               "\"real_time_factor\": %.6g, \"state_events\": %ld, \"time_events\": %ld, "
               "\"state_events_per_sim_s\": %.6g, \"state_events_per_wall_s\": %.6g, "
               "\"events_per_wall_s\": %.6g, \"solver_steps\": %ld, \"rhs_evaluations\": %ld, "
               "\"dostep_us_median\": %.6g, \"dostep_us_p99\": %.6g, \"dostep_us_max\": %.6g, "
               "\"dostep_calls\": %ld, \"max_tracking_error_m\": %.6g, \"wall_s_floor\": %.6g}\n",
               sim, reps, best_wall, mean_wall, sim / mean_wall, n_state, n_time, n_state / sim,
               n_state / mean_wall, (n_state + n_time) / mean_wall, n_steps, n_rhs,
               1e6 * quantile(walls, total, 0.5), 1e6 * quantile(walls, total, 0.99), 1e6 * walls[total - 1],
               total, max_err, wall_floor);
    }
    free(walls);
    fmi_api_unload(&api);
    return 0;
}
