/*
 * A small FMI 2.0 Co-Simulation FMU for the importer's tests: a damped oscillator
 *
 *     m x'' + d x' + k x = gain * F(t)
 *
 * integrated with classical RK4 on an internal grid of at most 1 ms per communication
 * step. `gain` is read from resources/gain.txt through fmuResourceLocation, so a wrong
 * resource URI makes fmi2Instantiate fail.
 *
 * Compile-time switches make the misbehaving variants the tests need:
 *
 *   -DFAIL_AT=t            fmi2DoStep returns fmi2Error for a step ending after t
 *   -DDISCARD_AT=t         fmi2DoStep integrates up to t and returns fmi2Discard
 *   -DDISCARD_TERMINATE=1  ... and reports fmi2Terminated = true (default false)
 *   -DNAN_AT=t             x becomes NaN once the time passes t (fmi2DoStep still OK)
 *   -DOMIT_GET_REAL_STATUS the library does not export fmi2GetRealStatus
 *   -DCRASH_AT=t           fmi2DoStep for a step ending after t ends the process or never
 *                          returns, by -DCRASH_HOW: 1 segfault (a write through NULL),
 *                          2 abort(), 3 exit(0), 4 hang
 *   -DCRASH_IN_INSTANTIATE fmi2Instantiate segfaults (a write through NULL)
 *
 * Value references: Real k=0 d=1 m=2 x0=3 F=4 x=5 v=6 a=7; Integer steps=0;
 * Boolean moving_right=0; String label=0.
 */
#include "fmi2.h"

#include <math.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#define GUID "{5c9a3c1e-7f7e-4d8f-9a43-0c2b7d1e6a21}"
#define N_REALS 8
#define STATE_MAGIC 0x05C1A7E5u

enum { VR_K, VR_D, VR_M, VR_X0, VR_F, VR_X, VR_V, VR_A };

typedef enum { INSTANTIATED, INITIALIZATION, STEPPING, TERMINATED, FAILED } Phase;

/* Everything that makes up the dynamic state; FMU states are copies of this. */
typedef struct {
    unsigned magic;
    double r[N_REALS];
    double time;
    double gain;
    int steps;
    int terminated;
    double last_successful_time;
    Phase phase;
    char label[64];
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

static void compute_acceleration(State *s) {
    s->r[VR_A] = (s->gain * s->r[VR_F] - s->r[VR_D] * s->r[VR_V] - s->r[VR_K] * s->r[VR_X]) /
                 s->r[VR_M];
}

/* Advance x, v from s->time by h with RK4 (F held constant over the step). */
static void rk4(State *s, double h) {
    double k = s->r[VR_K], d = s->r[VR_D], m = s->r[VR_M], f = s->gain * s->r[VR_F];
    double x = s->r[VR_X], v = s->r[VR_V];
    double k1x = v, k1v = (f - d * v - k * x) / m;
    double k2x = v + 0.5 * h * k1v, k2v = (f - d * (v + 0.5 * h * k1v) - k * (x + 0.5 * h * k1x)) / m;
    double k3x = v + 0.5 * h * k2v, k3v = (f - d * (v + 0.5 * h * k2v) - k * (x + 0.5 * h * k2x)) / m;
    double k4x = v + h * k3v, k4v = (f - d * (v + h * k3v) - k * (x + h * k3x)) / m;
    s->r[VR_X] = x + h / 6.0 * (k1x + 2.0 * k2x + 2.0 * k3x + k4x);
    s->r[VR_V] = v + h / 6.0 * (k1v + 2.0 * k2v + 2.0 * k3v + k4v);
    s->time += h;
}

/* Integrate from s->time to t_end on an internal grid of at most 1 ms. */
static void integrate(State *s, double t_end) {
    double span = t_end - s->time;
    int n = (int)ceil(span / 1e-3 - 1e-9);
    int i;
    if (n < 1) n = 1;
    for (i = 0; i < n; i++) rk4(s, span / n);
    s->time = t_end;
    compute_acceleration(s);
}

static int percent_decode(const char *in, char *out, size_t size) {
    size_t j = 0;
    for (; *in; in++) {
        unsigned value;
        if (j + 1 >= size) return 0;
        if (in[0] == '%' && in[1] && in[2] && sscanf(in + 1, "%2x", &value) == 1) {
            out[j++] = (char)value;
            in += 2;
        } else {
            out[j++] = *in;
        }
    }
    out[j] = '\0';
    return 1;
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
    char path[4096], file[4200];
    FILE *fp;
    (void)visible; (void)loggingOn;
#ifdef CRASH_IN_INSTANTIATE
    *(volatile int *)0 = 0; /* a real fault, not a raised signal */
#endif
    if (!functions || !functions->logger) return NULL;
    inst = (Instance *)calloc(1, sizeof(Instance));
    if (!inst) return NULL;
    memcpy((void *)&inst->callbacks, functions, sizeof(fmi2CallbackFunctions));
    snprintf(inst->instance_name, sizeof inst->instance_name, "%s", instanceName ? instanceName : "");
    if (fmuType != fmi2CoSimulation) {
        LOG(inst, fmi2Error, "logStatusError", "fmuType %d is not supported", (int)fmuType);
        free(inst);
        return NULL;
    }
    if (!guid || strcmp(guid, GUID) != 0) {
        LOG(inst, fmi2Error, "logStatusError", "wrong GUID %s, expected %s", guid ? guid : "(null)", GUID);
        free(inst);
        return NULL;
    }
    if (!resourceLocation || strncmp(resourceLocation, "file://", 7) != 0 ||
        !percent_decode(resourceLocation + 7, path, sizeof path)) {
        LOG(inst, fmi2Error, "logStatusError", "cannot use fmuResourceLocation \"%s\"",
            resourceLocation ? resourceLocation : "(null)");
        free(inst);
        return NULL;
    }
    snprintf(file, sizeof file, "%s/gain.txt", path);
    fp = fopen(file, "r");
    if (!fp || fscanf(fp, "%lf", &inst->s.gain) != 1) {
        LOG(inst, fmi2Error, "logStatusError", "cannot read %s", file);
        if (fp) fclose(fp);
        free(inst);
        return NULL;
    }
    fclose(fp);
    inst->s.magic = STATE_MAGIC;
    inst->s.r[VR_K] = 4.0;
    inst->s.r[VR_D] = 0.4;
    inst->s.r[VR_M] = 1.0;
    inst->s.r[VR_X0] = 1.0;
    inst->s.r[VR_F] = 0.0;
    inst->s.phase = INSTANTIATED;
    snprintf(inst->s.label, sizeof inst->s.label, "osc");
    return inst;
}

FMI2_Export void fmi2FreeInstance(fmi2Component c) { free(c); }

FMI2_Export fmi2Status fmi2SetupExperiment(fmi2Component c, fmi2Boolean toleranceDefined,
                                           fmi2Real tolerance, fmi2Real startTime,
                                           fmi2Boolean stopTimeDefined, fmi2Real stopTime) {
    Instance *inst = (Instance *)c;
    (void)toleranceDefined; (void)tolerance; (void)stopTimeDefined; (void)stopTime;
    inst->s.time = startTime;
    inst->s.last_successful_time = startTime;
    return fmi2OK;
}

FMI2_Export fmi2Status fmi2EnterInitializationMode(fmi2Component c) {
    ((Instance *)c)->s.phase = INITIALIZATION;
    return fmi2OK;
}

FMI2_Export fmi2Status fmi2ExitInitializationMode(fmi2Component c) {
    Instance *inst = (Instance *)c;
    inst->s.r[VR_X] = inst->s.r[VR_X0];
    inst->s.r[VR_V] = 0.0;
    compute_acceleration(&inst->s);
    inst->s.phase = STEPPING;
    LOG(inst, fmi2OK, "logEvents", "initialized: x=%g gain=%g label=%s", inst->s.r[VR_X],
        inst->s.gain, inst->s.label);
    return fmi2OK;
}

FMI2_Export fmi2Status fmi2Terminate(fmi2Component c) {
    ((Instance *)c)->s.phase = TERMINATED;
    return fmi2OK;
}

FMI2_Export fmi2Status fmi2Reset(fmi2Component c) {
    Instance *inst = (Instance *)c;
    double gain = inst->s.gain;
    memset(&inst->s, 0, sizeof inst->s);
    inst->s.magic = STATE_MAGIC;
    inst->s.gain = gain;
    inst->s.r[VR_K] = 4.0;
    inst->s.r[VR_D] = 0.4;
    inst->s.r[VR_M] = 1.0;
    inst->s.r[VR_X0] = 1.0;
    inst->s.phase = INSTANTIATED;
    snprintf(inst->s.label, sizeof inst->s.label, "osc");
    return fmi2OK;
}

FMI2_Export fmi2Status fmi2GetReal(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
                                   fmi2Real value[]) {
    Instance *inst = (Instance *)c;
    size_t i;
    for (i = 0; i < nvr; i++) {
        if (vr[i] >= N_REALS) {
            LOG(inst, fmi2Error, "logStatusError", "fmi2GetReal: unknown value reference %u", vr[i]);
            return fmi2Error;
        }
        value[i] = inst->s.r[vr[i]];
    }
    return fmi2OK;
}

FMI2_Export fmi2Status fmi2GetInteger(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
                                      fmi2Integer value[]) {
    Instance *inst = (Instance *)c;
    size_t i;
    for (i = 0; i < nvr; i++) {
        if (vr[i] != 0) {
            LOG(inst, fmi2Error, "logStatusError", "fmi2GetInteger: unknown value reference %u", vr[i]);
            return fmi2Error;
        }
        value[i] = inst->s.steps;
    }
    return fmi2OK;
}

FMI2_Export fmi2Status fmi2GetBoolean(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
                                      fmi2Boolean value[]) {
    Instance *inst = (Instance *)c;
    size_t i;
    for (i = 0; i < nvr; i++) {
        if (vr[i] != 0) {
            LOG(inst, fmi2Error, "logStatusError", "fmi2GetBoolean: unknown value reference %u", vr[i]);
            return fmi2Error;
        }
        value[i] = inst->s.r[VR_V] > 0.0 ? fmi2True : fmi2False;
    }
    return fmi2OK;
}

FMI2_Export fmi2Status fmi2GetString(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
                                     fmi2String value[]) {
    Instance *inst = (Instance *)c;
    size_t i;
    for (i = 0; i < nvr; i++) {
        if (vr[i] != 0) {
            LOG(inst, fmi2Error, "logStatusError", "fmi2GetString: unknown value reference %u", vr[i]);
            return fmi2Error;
        }
        value[i] = inst->s.label;
    }
    return fmi2OK;
}

FMI2_Export fmi2Status fmi2SetReal(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
                                   const fmi2Real value[]) {
    Instance *inst = (Instance *)c;
    size_t i;
    for (i = 0; i < nvr; i++) {
        if (vr[i] > VR_F) {
            LOG(inst, fmi2Error, "logStatusError", "fmi2SetReal: value reference %u cannot be set", vr[i]);
            return fmi2Error;
        }
        if (inst->s.phase == STEPPING && vr[i] != VR_F && vr[i] != VR_D) {
            LOG(inst, fmi2Error, "logStatusError",
                "fmi2SetReal: value reference %u is fixed after initialization", vr[i]);
            return fmi2Error;
        }
        if (vr[i] == VR_M && !(value[i] > 0.0)) {
            LOG(inst, fmi2Error, "logStatusError", "fmi2SetReal: mass must be positive, got %g", value[i]);
            return fmi2Error;
        }
        inst->s.r[vr[i]] = value[i];
    }
    return fmi2OK;
}

FMI2_Export fmi2Status fmi2SetInteger(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
                                      const fmi2Integer value[]) {
    Instance *inst = (Instance *)c;
    (void)vr; (void)value;
    if (nvr == 0) return fmi2OK;
    LOG(inst, fmi2Error, "logStatusError", "fmi2SetInteger: no settable Integer variables");
    return fmi2Error;
}

FMI2_Export fmi2Status fmi2SetBoolean(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
                                      const fmi2Boolean value[]) {
    Instance *inst = (Instance *)c;
    (void)vr; (void)value;
    if (nvr == 0) return fmi2OK;
    LOG(inst, fmi2Error, "logStatusError", "fmi2SetBoolean: no settable Boolean variables");
    return fmi2Error;
}

FMI2_Export fmi2Status fmi2SetString(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
                                     const fmi2String value[]) {
    Instance *inst = (Instance *)c;
    size_t i;
    for (i = 0; i < nvr; i++) {
        if (vr[i] != 0 || inst->s.phase == STEPPING) {
            LOG(inst, fmi2Error, "logStatusError", "fmi2SetString: value reference %u cannot be set", vr[i]);
            return fmi2Error;
        }
        snprintf(inst->s.label, sizeof inst->s.label, "%s", value[i]);
    }
    return fmi2OK;
}

FMI2_Export fmi2Status fmi2GetFMUstate(fmi2Component c, fmi2FMUstate *state) {
    Instance *inst = (Instance *)c;
    if (*state == NULL) {
        *state = malloc(sizeof(State));
        if (*state == NULL) return fmi2Error;
    }
    memcpy(*state, &inst->s, sizeof(State));
    return fmi2OK;
}

FMI2_Export fmi2Status fmi2SetFMUstate(fmi2Component c, fmi2FMUstate state) {
    Instance *inst = (Instance *)c;
    if (state == NULL || ((State *)state)->magic != STATE_MAGIC) {
        LOG(inst, fmi2Error, "logStatusError", "fmi2SetFMUstate: invalid state");
        return fmi2Error;
    }
    memcpy(&inst->s, state, sizeof(State));
    return fmi2OK;
}

FMI2_Export fmi2Status fmi2FreeFMUstate(fmi2Component c, fmi2FMUstate *state) {
    (void)c;
    if (state) {
        free(*state);
        *state = NULL;
    }
    return fmi2OK;
}

FMI2_Export fmi2Status fmi2SerializedFMUstateSize(fmi2Component c, fmi2FMUstate state, size_t *size) {
    (void)c; (void)state;
    *size = sizeof(State);
    return fmi2OK;
}

FMI2_Export fmi2Status fmi2SerializeFMUstate(fmi2Component c, fmi2FMUstate state,
                                             fmi2Byte serializedState[], size_t size) {
    Instance *inst = (Instance *)c;
    if (size != sizeof(State)) {
        LOG(inst, fmi2Error, "logStatusError", "fmi2SerializeFMUstate: size %zu, expected %zu", size, sizeof(State));
        return fmi2Error;
    }
    memcpy(serializedState, state, sizeof(State));
    return fmi2OK;
}

FMI2_Export fmi2Status fmi2DeSerializeFMUstate(fmi2Component c, const fmi2Byte serializedState[],
                                               size_t size, fmi2FMUstate *state) {
    Instance *inst = (Instance *)c;
    State tmp;
    if (size != sizeof(State)) {
        LOG(inst, fmi2Error, "logStatusError", "fmi2DeSerializeFMUstate: got %zu bytes, expected %zu", size, sizeof(State));
        return fmi2Error;
    }
    memcpy(&tmp, serializedState, sizeof(State));
    if (tmp.magic != STATE_MAGIC) {
        LOG(inst, fmi2Error, "logStatusError", "fmi2DeSerializeFMUstate: not a serialized state of this FMU");
        return fmi2Error;
    }
    if (*state == NULL) {
        *state = malloc(sizeof(State));
        if (*state == NULL) return fmi2Error;
    }
    memcpy(*state, &tmp, sizeof(State));
    return fmi2OK;
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
    LOG(inst, fmi2Error, "logStatusError", "fmi2SetRealInputDerivatives: cannot interpolate inputs");
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
    double t_end = currentCommunicationPoint + communicationStepSize;
    (void)noSetFMUStatePriorToCurrentPoint;
    if (inst->s.phase != STEPPING) {
        LOG(inst, fmi2Error, "logStatusError", "fmi2DoStep called outside step mode");
        return fmi2Error;
    }
    if (communicationStepSize <= 0.0) {
        LOG(inst, fmi2Error, "logStatusError", "fmi2DoStep: step size %g must be positive", communicationStepSize);
        return fmi2Error;
    }
    if (fabs(currentCommunicationPoint - inst->s.time) > 1e-9 * (1.0 + fabs(inst->s.time))) {
        LOG(inst, fmi2Error, "logStatusError", "fmi2DoStep: communication point %.17g differs from the FMU time %.17g",
            currentCommunicationPoint, inst->s.time);
        return fmi2Error;
    }
#ifdef CRASH_AT
    if (t_end > CRASH_AT) {
#if CRASH_HOW == 1
        *(volatile int *)0 = 0; /* a real fault, not a raised signal */
#elif CRASH_HOW == 2
        abort();
#elif CRASH_HOW == 3
        exit(0);
#else
        for (;;) sleep(1);
#endif
    }
#endif
#ifdef FAIL_AT
    if (t_end > FAIL_AT) {
        LOG(inst, fmi2Error, "logStatusError", "DoStep failed at t=%g (the solver diverged, h=%g)",
            currentCommunicationPoint, communicationStepSize);
        inst->s.phase = FAILED;
        return fmi2Error;
    }
#endif
#ifdef DISCARD_AT
    if (t_end > DISCARD_AT) {
        if (DISCARD_AT > inst->s.time) integrate(&inst->s, DISCARD_AT);
        inst->s.last_successful_time = inst->s.time;
#if defined(DISCARD_TERMINATE) && DISCARD_TERMINATE
        inst->s.terminated = 1;
        LOG(inst, fmi2Discard, "logStatusDiscard", "end of the model's data reached at t=%g", inst->s.time);
#else
        LOG(inst, fmi2Discard, "logStatusDiscard", "cannot step beyond t=%g", inst->s.time);
#endif
        return fmi2Discard;
    }
#endif
    integrate(&inst->s, t_end);
    inst->s.steps += 1;
    inst->s.last_successful_time = inst->s.time;
#ifdef NAN_AT
    if (inst->s.time > NAN_AT) inst->s.r[VR_X] = NAN;
#endif
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
    LOG(inst, fmi2Error, "logStatusError", "fmi2GetStatus(%d): not available", (int)s);
    return fmi2Discard;
}

#ifndef OMIT_GET_REAL_STATUS
FMI2_Export fmi2Status fmi2GetRealStatus(fmi2Component c, const fmi2StatusKind s, fmi2Real *value) {
    Instance *inst = (Instance *)c;
    if (s != fmi2LastSuccessfulTime) {
        LOG(inst, fmi2Error, "logStatusError", "fmi2GetRealStatus(%d): not available", (int)s);
        return fmi2Discard;
    }
    *value = inst->s.last_successful_time;
    return fmi2OK;
}
#endif

FMI2_Export fmi2Status fmi2GetIntegerStatus(fmi2Component c, const fmi2StatusKind s, fmi2Integer *value) {
    Instance *inst = (Instance *)c;
    (void)value;
    LOG(inst, fmi2Error, "logStatusError", "fmi2GetIntegerStatus(%d): not available", (int)s);
    return fmi2Discard;
}

FMI2_Export fmi2Status fmi2GetBooleanStatus(fmi2Component c, const fmi2StatusKind s, fmi2Boolean *value) {
    Instance *inst = (Instance *)c;
    if (s != fmi2Terminated) {
        LOG(inst, fmi2Error, "logStatusError", "fmi2GetBooleanStatus(%d): not available", (int)s);
        return fmi2Discard;
    }
    *value = inst->s.terminated ? fmi2True : fmi2False;
    return fmi2OK;
}

FMI2_Export fmi2Status fmi2GetStringStatus(fmi2Component c, const fmi2StatusKind s, fmi2String *value) {
    Instance *inst = (Instance *)c;
    (void)value;
    LOG(inst, fmi2Error, "logStatusError", "fmi2GetStringStatus(%d): not available", (int)s);
    return fmi2Discard;
}
