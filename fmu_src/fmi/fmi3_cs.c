/* FMI 3.0 co-simulation: fmi3DoStep is fmi2DoStep's step (fmu_cs_do_step, fmi2_cs.c) plus
 * event mode and early return at a friction switch. During a step fmu_event_update calls
 * fmi3_on_switch after every switch; the first one after the step's start is snapshotted (the
 * whole model, right after its event update). With earlyReturnAllowed the step then returns
 * at that switch: the instance is set back to the snapshot, so the trajectory is the one the
 * full step computed, cut at the switch (the work past it is discarded). With eventModeUsed
 * the step reports eventHandlingNeeded when a switch happened (the FMU has already made the
 * update there; in Event Mode the master may set inputs at that instant). No intermediate
 * update (providesIntermediateUpdate is false). */
#include <string.h>

#include "fmi3_glue.h"

void fmi3_on_switch(void *instance) {
    instance_t *c = (instance_t *)instance;
    fmi3_ext_t *e = fmi3_ext(c);
    if (!e || !e->armed || !(c->m.time > e->step_t0)) return;
    e->n_switches++;
    if (!e->taken) {
        e->snap = c->m;
        e->taken = 1;
    }
}

fmi3Status fmi3EnterStepMode(fmi3Instance instance) {
    instance_t *c = FMU_ENTER(instance, fmi3EnterStepMode);
    if (!c) return fmi3Error;
    c->m.fsm = ST_STEP_COMPLETE;
    return fmi3OK;
}

fmi3Status fmi3DoStep(fmi3Instance instance, fmi3Float64 currentCommunicationPoint, fmi3Float64 communicationStepSize,
                      fmi3Boolean noSetFMUStatePriorToCurrentPoint, fmi3Boolean *eventHandlingNeeded,
                      fmi3Boolean *terminateSimulation, fmi3Boolean *earlyReturn, fmi3Float64 *lastSuccessfulTime) {
    instance_t *c = FMU_ENTER(instance, fmi3DoStep);
    fmi3_ext_t *e;
    fmi2Status st;
    (void)noSetFMUStatePriorToCurrentPoint;
    if (!c) return fmi3Error;
    if (!eventHandlingNeeded || !terminateSimulation || !earlyReturn || !lastSuccessfulTime) {
        fmu_log(c, fmi2Error, LOG_ERROR, "fmi3DoStep: NULL output argument");
        return fmi3Error;
    }
    e = fmi3_ext(c);
    *eventHandlingNeeded = *terminateSimulation = *earlyReturn = fmi3False;
    e->armed = e->event_mode_used || e->early_return_allowed;
    e->taken = 0;
    e->n_switches = 0;
    e->step_t0 = currentCommunicationPoint;
    st = fmu_cs_do_step(c, currentCommunicationPoint, communicationStepSize);
    e->armed = 0;
    if (st != fmi2OK) { *lastSuccessfulTime = c->m.time; return (fmi3Status)st; }
    /* a switch on the step's end is no early return: the step ends there anyway */
    if (e->taken && e->early_return_allowed && e->snap.time < c->m.time) {
        c->m = e->snap;
        c->m.solver_restart = 1;   /* the step's integrator restarted after the switch, so does the next */
        c->m.out_valid = 0;
        *earlyReturn = fmi3True;
    }
    *eventHandlingNeeded = e->event_mode_used && e->taken;
    *lastSuccessfulTime = c->m.time;
    return fmi3OK;
}

fmi3Status fmi3GetOutputDerivatives(fmi3Instance instance, const fmi3ValueReference valueReferences[],
                                    size_t nValueReferences, const fmi3Int32 orders[], fmi3Float64 values[],
                                    size_t nValues) {
    instance_t *c = FMU_ENTER(instance, fmi3GetOutputDerivatives);
    if (!c) return fmi3Error;
    if (nValues != nValueReferences) {
        fmu_log(c, fmi2Error, LOG_ERROR, "fmi3GetOutputDerivatives: nValues = %zu, allowed %zu (scalar outputs "
                "x, v and i)", nValues, nValueReferences);
        return fmi3Error;
    }
    return (fmi3Status)fmi2GetRealOutputDerivatives(c, valueReferences, nValueReferences, orders, values);
}
