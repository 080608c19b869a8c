/*
 * A tiny FMI 2.0 Co-Simulation FMU for the tests of Integer and Boolean connections: two
 * instances wired in a loop show how a master orders the exchange (Jacobi or Gauss-Seidel).
 *
 * Model. There is no direct feedthrough: the outputs change only at the end of fmi2DoStep,
 * from the inputs that were set before that step,
 *
 *     n_out = n_in + increment,     b_out = !b_in,     y_out = u_in + h
 *
 * (h the communication step size). Before the first step the outputs are their start
 * values 0, false, 0 whatever the inputs are. The model time advances by t += h per step.
 *
 * Variables (value references unique over all types, so a master that mixes up the types
 * gets fmi2Error instead of a wrong value):
 *   Integer  0 n_in (input)   1 n_out (output)   2 increment (parameter, fixed, start 1)
 *   Boolean  3 b_in (input)   4 b_out (output)
 *   Real     5 u_in (input)   6 y_out (output)
 * The parameter may be set until fmi2ExitInitializationMode; outputs cannot be set.
 * FMU states are not supported (canGetAndSetFMUstate="false").
 */
#include "fmi2.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define GUID "{3f6b2d94-71c8-4e0a-b5d2-9c41a7e08f13}"
#define TIME_TOLERANCE 1e-9

enum { VR_N_IN, VR_N_OUT, VR_INCREMENT, VR_B_IN, VR_B_OUT, VR_U_IN, VR_Y_OUT };

typedef enum { INSTANTIATED, INITIALIZATION, STEPPING, TERMINATED } Phase;

typedef struct {
    Phase phase;
    double start_time;
    double time;             /* FMI time: communication point + step size */
    double last_successful_time;
    int n_in, increment, n_out;
    int b_in, b_out;         /* fmi2True / fmi2False */
    double u_in, y_out;
} State;

typedef struct {
    State s;
    char instance_name[128];
    fmi2CallbackFunctions callbacks;
} Instance;

#define LOG(inst, status, category, ...)                                                   \
    do {                                                                                   \
        if ((inst)->callbacks.logger)                                                      \
            (inst)->callbacks.logger((inst)->callbacks.componentEnvironment,               \
                                     (inst)->instance_name, (status), (category),          \
                                     __VA_ARGS__);                                         \
    } while (0)

static void set_defaults(State *s) {
    memset(s, 0, sizeof *s);
    s->phase = INSTANTIATED;
    s->increment = 1;
    s->b_in = fmi2False;
    s->b_out = fmi2False;
}

static int nonempty(fmi2String s) { return s && s[0] != '\0'; }

/* Setting an input: allowed until fmi2Terminate. */
static int may_set_input(Instance *inst, const char *fn) {
    if (inst->s.phase == TERMINATED) {
        LOG(inst, fmi2Error, "logStatusError", "%s: the FMU is terminated", fn);
        return 0;
    }
    return 1;
}

static fmi2Status not_a(Instance *inst, const char *fn, fmi2ValueReference vr, const char *what) {
    LOG(inst, fmi2Error, "logStatusError", "%s: value reference %u is not %s", fn, vr, what);
    return fmi2Error;
}

FMI2_Export const char *fmi2GetTypesPlatform(void) { return "default"; }
FMI2_Export const char *fmi2GetVersion(void) { return "2.0"; }

FMI2_Export fmi2Status fmi2SetDebugLogging(fmi2Component c, fmi2Boolean on, size_t n,
                                           const fmi2String categories[]) {
    (void)c; (void)on; (void)n; (void)categories;
    return fmi2OK;
}

FMI2_Export fmi2Component fmi2Instantiate(fmi2String instanceName, fmi2Type fmuType,
                                          fmi2String guid, fmi2String resourceLocation,
                                          const fmi2CallbackFunctions *functions,
                                          fmi2Boolean visible, fmi2Boolean loggingOn) {
    Instance *inst;
    (void)resourceLocation; (void)visible; (void)loggingOn;
    if (!functions || !functions->logger) return NULL;
    inst = (Instance *)calloc(1, sizeof(Instance));
    if (!inst) return NULL;
    memcpy((void *)&inst->callbacks, functions, sizeof(fmi2CallbackFunctions));
    snprintf(inst->instance_name, sizeof inst->instance_name, "%s", instanceName ? instanceName : "");
    if (fmuType != fmi2CoSimulation) {
        LOG(inst, fmi2Error, "logStatusError", "fmuType %d is not supported (Co-Simulation only)", (int)fmuType);
        free(inst);
        return NULL;
    }
    if (!nonempty(guid) || strcmp(guid, GUID) != 0) {
        LOG(inst, fmi2Error, "logStatusError", "wrong GUID \"%s\", expected %s", guid ? guid : "(null)", GUID);
        free(inst);
        return NULL;
    }
    set_defaults(&inst->s);
    return inst;
}

FMI2_Export void fmi2FreeInstance(fmi2Component c) { free(c); }

FMI2_Export fmi2Status fmi2SetupExperiment(fmi2Component c, fmi2Boolean toleranceDefined,
                                           fmi2Real tolerance, fmi2Real startTime,
                                           fmi2Boolean stopTimeDefined, fmi2Real stopTime) {
    Instance *inst = (Instance *)c;
    (void)toleranceDefined; (void)tolerance;
    if (inst->s.phase != INSTANTIATED) {
        LOG(inst, fmi2Error, "logStatusError", "fmi2SetupExperiment is only allowed after fmi2Instantiate");
        return fmi2Error;
    }
    if (!isfinite(startTime) || (stopTimeDefined && !(isfinite(stopTime) && stopTime >= startTime))) {
        LOG(inst, fmi2Error, "logStatusError", "fmi2SetupExperiment: bad start time %g or stop time %g",
            startTime, stopTime);
        return fmi2Error;
    }
    inst->s.start_time = startTime;
    inst->s.time = startTime;
    inst->s.last_successful_time = startTime;
    return fmi2OK;
}

FMI2_Export fmi2Status fmi2EnterInitializationMode(fmi2Component c) {
    Instance *inst = (Instance *)c;
    if (inst->s.phase != INSTANTIATED) {
        LOG(inst, fmi2Error, "logStatusError", "fmi2EnterInitializationMode is only allowed after fmi2Instantiate");
        return fmi2Error;
    }
    inst->s.phase = INITIALIZATION;
    return fmi2OK;
}

FMI2_Export fmi2Status fmi2ExitInitializationMode(fmi2Component c) {
    Instance *inst = (Instance *)c;
    if (inst->s.phase != INITIALIZATION) {
        LOG(inst, fmi2Error, "logStatusError", "fmi2ExitInitializationMode outside initialization mode");
        return fmi2Error;
    }
    inst->s.phase = STEPPING;
    LOG(inst, fmi2OK, "logEvents", "initialized at t = %g with increment %d", inst->s.time, inst->s.increment);
    return fmi2OK;
}

FMI2_Export fmi2Status fmi2Terminate(fmi2Component c) {
    Instance *inst = (Instance *)c;
    if (inst->s.phase != STEPPING) {
        LOG(inst, fmi2Error, "logStatusError", "fmi2Terminate is only allowed in step mode");
        return fmi2Error;
    }
    inst->s.phase = TERMINATED;
    return fmi2OK;
}

FMI2_Export fmi2Status fmi2Reset(fmi2Component c) {
    set_defaults(&((Instance *)c)->s);
    return fmi2OK;
}

FMI2_Export fmi2Status fmi2GetReal(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
                                   fmi2Real value[]) {
    Instance *inst = (Instance *)c;
    size_t n;
    for (n = 0; n < nvr; n++) {
        if (vr[n] == VR_U_IN) value[n] = inst->s.u_in;
        else if (vr[n] == VR_Y_OUT) value[n] = inst->s.y_out;
        else return not_a(inst, "fmi2GetReal", vr[n], "a Real variable");
    }
    return fmi2OK;
}

FMI2_Export fmi2Status fmi2GetInteger(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
                                      fmi2Integer value[]) {
    Instance *inst = (Instance *)c;
    size_t n;
    for (n = 0; n < nvr; n++) {
        if (vr[n] == VR_N_IN) value[n] = inst->s.n_in;
        else if (vr[n] == VR_N_OUT) value[n] = inst->s.n_out;
        else if (vr[n] == VR_INCREMENT) value[n] = inst->s.increment;
        else return not_a(inst, "fmi2GetInteger", vr[n], "an Integer variable");
    }
    return fmi2OK;
}

FMI2_Export fmi2Status fmi2GetBoolean(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
                                      fmi2Boolean value[]) {
    Instance *inst = (Instance *)c;
    size_t n;
    for (n = 0; n < nvr; n++) {
        if (vr[n] == VR_B_IN) value[n] = inst->s.b_in;
        else if (vr[n] == VR_B_OUT) value[n] = inst->s.b_out;
        else return not_a(inst, "fmi2GetBoolean", vr[n], "a Boolean variable");
    }
    return fmi2OK;
}

FMI2_Export fmi2Status fmi2GetString(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
                                     fmi2String value[]) {
    Instance *inst = (Instance *)c;
    (void)vr; (void)value;
    if (nvr == 0) return fmi2OK;
    LOG(inst, fmi2Error, "logStatusError", "fmi2GetString: the FMU has no String variables");
    return fmi2Error;
}

FMI2_Export fmi2Status fmi2SetReal(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
                                   const fmi2Real value[]) {
    Instance *inst = (Instance *)c;
    size_t n;
    for (n = 0; n < nvr; n++) {
        if (vr[n] != VR_U_IN) return not_a(inst, "fmi2SetReal", vr[n], "a Real input");
        if (!isfinite(value[n])) {
            LOG(inst, fmi2Error, "logStatusError", "fmi2SetReal: value reference %u cannot be set to %g", vr[n], value[n]);
            return fmi2Error;
        }
        if (!may_set_input(inst, "fmi2SetReal")) return fmi2Error;
        inst->s.u_in = value[n];
    }
    return fmi2OK;
}

FMI2_Export fmi2Status fmi2SetInteger(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
                                      const fmi2Integer value[]) {
    Instance *inst = (Instance *)c;
    size_t n;
    for (n = 0; n < nvr; n++) {
        if (vr[n] == VR_INCREMENT) {
            if (inst->s.phase != INSTANTIATED && inst->s.phase != INITIALIZATION) {
                LOG(inst, fmi2Error, "logStatusError",
                    "fmi2SetInteger: parameter (value reference %u) is fixed after initialisation", vr[n]);
                return fmi2Error;
            }
            inst->s.increment = value[n];
        } else if (vr[n] == VR_N_IN) {
            if (!may_set_input(inst, "fmi2SetInteger")) return fmi2Error;
            inst->s.n_in = value[n];
        } else {
            return not_a(inst, "fmi2SetInteger", vr[n], "an Integer input or parameter");
        }
    }
    return fmi2OK;
}

FMI2_Export fmi2Status fmi2SetBoolean(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
                                      const fmi2Boolean value[]) {
    Instance *inst = (Instance *)c;
    size_t n;
    for (n = 0; n < nvr; n++) {
        if (vr[n] != VR_B_IN) return not_a(inst, "fmi2SetBoolean", vr[n], "a Boolean input");
        if (!may_set_input(inst, "fmi2SetBoolean")) return fmi2Error;
        inst->s.b_in = value[n] ? fmi2True : fmi2False;
    }
    return fmi2OK;
}

FMI2_Export fmi2Status fmi2SetString(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
                                     const fmi2String value[]) {
    Instance *inst = (Instance *)c;
    (void)vr; (void)value;
    if (nvr == 0) return fmi2OK;
    LOG(inst, fmi2Error, "logStatusError", "fmi2SetString: the FMU has no String variables");
    return fmi2Error;
}

static fmi2Status no_states(fmi2Component c, const char *fn) {
    Instance *inst = (Instance *)c;
    LOG(inst, fmi2Error, "logStatusError", "%s: canGetAndSetFMUstate is false", fn);
    return fmi2Error;
}

FMI2_Export fmi2Status fmi2GetFMUstate(fmi2Component c, fmi2FMUstate *state) {
    (void)state;
    return no_states(c, "fmi2GetFMUstate");
}

FMI2_Export fmi2Status fmi2SetFMUstate(fmi2Component c, fmi2FMUstate state) {
    (void)state;
    return no_states(c, "fmi2SetFMUstate");
}

FMI2_Export fmi2Status fmi2FreeFMUstate(fmi2Component c, fmi2FMUstate *state) {
    (void)state;
    return no_states(c, "fmi2FreeFMUstate");
}

FMI2_Export fmi2Status fmi2SerializedFMUstateSize(fmi2Component c, fmi2FMUstate state, size_t *size) {
    (void)state; (void)size;
    return no_states(c, "fmi2SerializedFMUstateSize");
}

FMI2_Export fmi2Status fmi2SerializeFMUstate(fmi2Component c, fmi2FMUstate state,
                                             fmi2Byte serializedState[], size_t size) {
    (void)state; (void)serializedState; (void)size;
    return no_states(c, "fmi2SerializeFMUstate");
}

FMI2_Export fmi2Status fmi2DeSerializeFMUstate(fmi2Component c, const fmi2Byte serializedState[],
                                               size_t size, fmi2FMUstate *state) {
    (void)serializedState; (void)size; (void)state;
    return no_states(c, "fmi2DeSerializeFMUstate");
}

FMI2_Export fmi2Status fmi2GetDirectionalDerivative(fmi2Component c, const fmi2ValueReference vUnknown[],
                                                    size_t nUnknown, const fmi2ValueReference vKnown[],
                                                    size_t nKnown, const fmi2Real dvKnown[],
                                                    fmi2Real dvUnknown[]) {
    Instance *inst = (Instance *)c;
    (void)vUnknown; (void)nUnknown; (void)vKnown; (void)nKnown; (void)dvKnown; (void)dvUnknown;
    LOG(inst, fmi2Error, "logStatusError", "fmi2GetDirectionalDerivative is not provided");
    return fmi2Error;
}

FMI2_Export fmi2Status fmi2SetRealInputDerivatives(fmi2Component c, const fmi2ValueReference vr[],
                                                   size_t nvr, const fmi2Integer order[],
                                                   const fmi2Real value[]) {
    Instance *inst = (Instance *)c;
    (void)vr; (void)nvr; (void)order; (void)value;
    LOG(inst, fmi2Error, "logStatusError", "fmi2SetRealInputDerivatives: canInterpolateInputs is false");
    return fmi2Error;
}

FMI2_Export fmi2Status fmi2GetRealOutputDerivatives(fmi2Component c, const fmi2ValueReference vr[],
                                                    size_t nvr, const fmi2Integer order[],
                                                    fmi2Real value[]) {
    Instance *inst = (Instance *)c;
    (void)vr; (void)nvr; (void)order; (void)value;
    LOG(inst, fmi2Error, "logStatusError", "fmi2GetRealOutputDerivatives: maxOutputDerivativeOrder is 0");
    return fmi2Error;
}

FMI2_Export fmi2Status fmi2DoStep(fmi2Component c, fmi2Real currentCommunicationPoint,
                                  fmi2Real communicationStepSize,
                                  fmi2Boolean noSetFMUStatePriorToCurrentPoint) {
    Instance *inst = (Instance *)c;
    double t = currentCommunicationPoint, h = communicationStepSize;
    double now = inst->s.time;
    (void)noSetFMUStatePriorToCurrentPoint;
    if (inst->s.phase != STEPPING) {
        LOG(inst, fmi2Error, "logStatusError", "fmi2DoStep called outside step mode");
        return fmi2Error;
    }
    if (!isfinite(t) || !(isfinite(h) && h > 0.0)) {
        LOG(inst, fmi2Error, "logStatusError", "fmi2DoStep: bad communication point %g or step size %g", t, h);
        return fmi2Error;
    }
    if (fabs(t - now) > TIME_TOLERANCE * fmax(1.0, fabs(now))) {
        LOG(inst, fmi2Error, "logStatusError",
            "fmi2DoStep: communication point %.17g differs from the FMU time %.17g", t, now);
        return fmi2Error;
    }
    inst->s.n_out = inst->s.n_in + inst->s.increment;
    inst->s.b_out = inst->s.b_in ? fmi2False : fmi2True;
    inst->s.y_out = inst->s.u_in + h;
    inst->s.time = t + h;
    inst->s.last_successful_time = inst->s.time;
    return fmi2OK;
}

FMI2_Export fmi2Status fmi2CancelStep(fmi2Component c) {
    Instance *inst = (Instance *)c;
    LOG(inst, fmi2Error, "logStatusError", "fmi2CancelStep: fmi2DoStep is synchronous");
    return fmi2Error;
}

FMI2_Export fmi2Status fmi2GetStatus(fmi2Component c, const fmi2StatusKind s, fmi2Status *value) {
    Instance *inst = (Instance *)c;
    (void)value;
    LOG(inst, fmi2Discard, "logStatusDiscard", "fmi2GetStatus(%d): no asynchronous step exists", (int)s);
    return fmi2Discard;
}

FMI2_Export fmi2Status fmi2GetRealStatus(fmi2Component c, const fmi2StatusKind s, fmi2Real *value) {
    Instance *inst = (Instance *)c;
    if (s != fmi2LastSuccessfulTime || !value) {
        LOG(inst, fmi2Discard, "logStatusDiscard", "fmi2GetRealStatus(%d): not available", (int)s);
        return fmi2Discard;
    }
    *value = inst->s.last_successful_time;
    return fmi2OK;
}

FMI2_Export fmi2Status fmi2GetIntegerStatus(fmi2Component c, const fmi2StatusKind s, fmi2Integer *value) {
    Instance *inst = (Instance *)c;
    (void)value;
    LOG(inst, fmi2Discard, "logStatusDiscard", "fmi2GetIntegerStatus(%d): not available", (int)s);
    return fmi2Discard;
}

FMI2_Export fmi2Status fmi2GetBooleanStatus(fmi2Component c, const fmi2StatusKind s, fmi2Boolean *value) {
    Instance *inst = (Instance *)c;
    if (s != fmi2Terminated || !value) {
        LOG(inst, fmi2Discard, "logStatusDiscard", "fmi2GetBooleanStatus(%d): not available", (int)s);
        return fmi2Discard;
    }
    *value = fmi2False;
    return fmi2OK;
}

FMI2_Export fmi2Status fmi2GetStringStatus(fmi2Component c, const fmi2StatusKind s, fmi2String *value) {
    Instance *inst = (Instance *)c;
    (void)value;
    LOG(inst, fmi2Discard, "logStatusDiscard", "fmi2GetStringStatus(%d): not available", (int)s);
    return fmi2Discard;
}
