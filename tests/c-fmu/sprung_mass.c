/*
 * An "outside" vehicle FMU (FMI 2.0 Co-Simulation) written in C, sharing no code with the
 * project's crates: one sprung mass on one massless wheelset (Biggs; Yang & Yau 1997). It
 * plugs into the bridge FMU exactly like the project's train FMU with one sprung-mass axle:
 * same variable names, units, signs and input timing (dynamics/src/interface.rs,
 * fmu-train/src/layout.rs).
 *
 * Model. A body of mass m hangs on a spring k and a damper c above a massless wheel that
 * follows the rail vertically. Axes: x forward, y right, z DOWN. The body's DOF z is its
 * vertical displacement (+ down) measured from the static equilibrium on a rigid, level
 * rail; u, u', u'' are the vertical rail displacement, velocity and acceleration under the
 * wheel (inputs ws[1].z, ws[1].z_d, ws[1].z_dd). The equation of motion is
 *
 *     m z'' + c (z' - u') + k (z - u) = 0
 *
 * (gravity is balanced by the static spring preload, so it does not appear), and the
 * force of the wheel on the rail (+ down) is
 *
 *     F_z = P0 - k (u - z) - c (u' - z'),      P0 = m g  (static load; massless wheel),
 *
 * i.e. the project's  F_z = (m_s + m_w) g - m_w u'' - k (u_z - z) - c (u'_z - z')  with
 * m_w = 0 (dynamics/src/vehicle/simple.rs:1-7). F_y = M_x = 0 (no lateral or roll DOF).
 * The wheel position is x(t) = (x0 - v t0) + v t, t0 the start time, so x(t0) = x0
 * (dynamics/src/interface.rs TrainResources::build, dynamics/src/train.rs Train::x_at).
 *
 * The project writes this as a linear vehicle with K_vv = k, C_vv = c, M_vv = m and the
 * wheelset coupling K_vw = -k, C_vw = -c (vertical column), K_ww = k, C_ww = c, and a static
 * load P0 = -K_vw v_s with K_vv v_s = m g solved by Cholesky (vehicle/assembly.rs build), so
 * in floating point  P0 = -((-k) vs),  vs = ((m g)/sqrt(k))/sqrt(k).  All expressions below
 * are written in the same order of operations as the project's code, so the results agree
 * to the last bit on the same inputs (floating-point contraction is switched off below).
 *
 * Initial state (dynamics/src/solver/mod.rs VehicleState::initial, used by
 * TrainSide::initialize, partitioned.rs:249): static equilibrium on the rail motion given
 * at initialisation (u0, u0', u0''):
 *
 *     z0   = ((0 - (-k) u0)  / sqrt(k)) / sqrt(k)            (k z0  = k u0)
 *     z0'  = ((0 - (-k) u0') / sqrt(k)) / sqrt(k)            (k z0' = k u0', quasi-static)
 *     z0'' = (r / sqrt(m)) / sqrt(m),  r = (-(c z0') - k z0) - ((-k) u0 + (-c) u0')
 *
 * (so a body on a rail at rest starts at z = 0 with F_z = P0 = m g).
 *
 * Time step (dynamics/src/solver/partitioned.rs:263-306 TrainSide::step, with
 * dynamics/src/newmark.rs): Newmark average acceleration, beta = 1/4, gamma = 1/2,
 *
 *     z_{n+1}  = z_n + h z'_n + h^2/4 (z''_n + z''_{n+1})
 *     z'_{n+1} = z'_n + h/2 (z''_n + z''_{n+1})
 *
 * with the rail motion at the END of the step, u_{n+1}, u'_{n+1} (the inputs set before
 * fmi2DoStep(t, h) are the values at t + h), solved for the new acceleration:
 *
 *     zp  = (z_n + h z'_n) + (h^2/4) z''_n,     zdp = z'_n + (h/2) z''_n      (predictors)
 *     r   = (-(c zdp) - k zp) - ((-k) u_{n+1} + (-c) u'_{n+1})
 *     a0  = 4/h^2,  a1 = 2/h,  L = sqrt((a0 m + a1 c) + k)
 *     z''_{n+1} = ((a0 r) / L) / L            [= r / (m + h/2 c + h^2/4 k)]
 *     z_{n+1}   = zp + (h^2/4) z''_{n+1},     z'_{n+1} = zdp + (h/2) z''_{n+1}
 *
 * This acceleration form stays accurate for communication steps far below the nominal one.
 * Outputs after a step use the new state with the step's end rail motion
 * (vehicle/mod.rs LinearVehicle::wheel_force):
 *
 *     F_z = ((P0 - k u) - c u') - (0 + ((-k) z + (-c) z'))
 *
 * Before fmi2ExitInitializationMode the outputs are those of the initial state on the
 * current inputs at the start time (as the train FMU's refresh does); after it, setting
 * inputs does not change the outputs until the next fmi2DoStep (no direct feedthrough).
 * The model time advances by t += h per step (TrainSide::t).
 *
 * Variables (value references parallel to the train FMU with one wheelset and one vehicle):
 *   inputs   0..8   ws[1].y theta z y_d theta_d z_d y_dd theta_dd z_dd  (only z, z_d, z_dd used)
 *   outputs  9..13  ws[1].x vx F_y M_x F_z
 *            18 veh[1].a_y (= 0)  19 veh[1].a_z  20 veh[1].z  21 veh[1].v_z
 *   params   1000000 speed  1000001 x0  1000100 m  1000101 k  1000102 c  1000103 g
 * Parameters may be set until fmi2ExitInitializationMode; m > 0, k > 0, c >= 0,
 * 0 < speed <= 200 m/s (the project's Speed), every Real finite.
 */
#if defined(__clang__)
#pragma STDC FP_CONTRACT OFF
#elif defined(__GNUC__)
#pragma GCC optimize("fp-contract=off")
#endif

#include "fmi2.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define GUID "{8e1ec145-243b-4d41-882d-1b4d78c32a7a}"
#define STATE_MAGIC 0x5A1E55EDu
#define TIME_TOLERANCE 1e-12
#define MAX_SPEED 200.0

/* Defaults: the Yang-Yau case (master/tests/data/yang-yau.toml), gravity of
 * dynamics/src/vehicle/mod.rs GRAVITY, start at the deck start x = 0. */
#define DEFAULT_M 5750.0
#define DEFAULT_K 1.595e6
#define DEFAULT_C 0.0
#define DEFAULT_SPEED (100.0 / 3.6)
#define DEFAULT_X0 0.0
#define DEFAULT_G 9.81

/* Internal indices of the Real variables. */
enum {
    I_Y, I_THETA, I_Z, I_Y_D, I_THETA_D, I_Z_D, I_Y_DD, I_THETA_DD, I_Z_DD, /* inputs */
    O_X, O_VX, O_FY, O_MX, O_FZ, O_AY, O_AZ, O_Z, O_VZ,                    /* outputs */
    P_SPEED, P_X0, P_M, P_K, P_C, P_G,                                     /* parameters */
    N_VARS
};
#define N_INPUTS 9
#define FIRST_OUTPUT O_X
#define FIRST_PARAM P_SPEED

static const fmi2ValueReference VR_OF[N_VARS] = {
    0, 1, 2, 3, 4, 5, 6, 7, 8,
    9, 10, 11, 12, 13, 18, 19, 20, 21,
    1000000, 1000001, 1000100, 1000101, 1000102, 1000103,
};

static int index_of(fmi2ValueReference vr) {
    int i;
    for (i = 0; i < N_VARS; i++)
        if (VR_OF[i] == vr) return i;
    return -1;
}

typedef enum { INSTANTIATED, INITIALIZATION, STEPPING, TERMINATED, FAILED } Phase;

/* Everything that makes up the FMU's state; FMU states are copies of this. */
typedef struct {
    unsigned magic;
    Phase phase;
    double in[N_INPUTS];     /* rail inputs, RAIL_CHANNELS order */
    double p[N_VARS - FIRST_PARAM]; /* parameters, P_SPEED.. order */
    double start_time;
    int stop_defined;
    double stop_time;
    double time;             /* FMI time: communication point + step size */
    double last_successful_time;
    /* model, valid from fmi2ExitInitializationMode on */
    double t;                /* model time, t += h per step */
    double x0_t0;            /* x0 - v t0: the wheel's position at t = 0 */
    double p0;               /* static wheel load, N */
    double z, zd, zdd;       /* body displacement, velocity, acceleration (+ down) */
    double u, ud, udd;       /* vertical rail motion the current state was computed with */
} State;

#define PAR(s, i) ((s)->p[(i) - FIRST_PARAM])

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
    s->magic = STATE_MAGIC;
    s->phase = INSTANTIATED;
    PAR(s, P_SPEED) = DEFAULT_SPEED;
    PAR(s, P_X0) = DEFAULT_X0;
    PAR(s, P_M) = DEFAULT_M;
    PAR(s, P_K) = DEFAULT_K;
    PAR(s, P_C) = DEFAULT_C;
    PAR(s, P_G) = DEFAULT_G;
}

/* Static load P0 = -K_vw v_s with k v_s = m g (Cholesky of the 1x1 K_vv: L = sqrt(k)). */
static double static_load(double m, double k, double g) {
    double l = sqrt(k);
    double vs = ((m * g) / l) / l;
    return -((-k) * vs);
}

/* Build the model at the start time on the current inputs (TrainSide::initialize). */
static void initialize_model(State *s) {
    double m = PAR(s, P_M), k = PAR(s, P_K), c = PAR(s, P_C);
    double v = PAR(s, P_SPEED);
    double lk = sqrt(k), lm = sqrt(m);
    double fu, fud, rhs;
    s->t = s->start_time;
    s->x0_t0 = PAR(s, P_X0) - v * s->start_time;
    s->p0 = static_load(m, k, PAR(s, P_G));
    s->u = s->in[I_Z];
    s->ud = s->in[I_Z_D];
    s->udd = s->in[I_Z_DD];
    /* K v = -K_vw u, K v' = -K_vw u', M v'' = -C v' - K v - (K_vw u + C_vw u') */
    fu = 0.0 - (-k) * s->u;
    fud = 0.0 - (-k) * s->ud;
    s->z = (fu / lk) / lk;
    s->zd = (fud / lk) / lk;
    rhs = (-(c * s->zd) - k * s->z) - ((-k) * s->u + (-c) * s->ud);
    s->zdd = (rhs / lm) / lm;
}

/* One Newmark step of size h with the end-of-step rail motion (TrainSide::step). */
static void newmark_step(State *s, double h) {
    double m = PAR(s, P_M), k = PAR(s, P_K), c = PAR(s, P_C);
    double a0 = 4.0 / (h * h), a1 = 2.0 / h;
    double l = sqrt((a0 * m + a1 * c) + k);
    double u1 = s->in[I_Z], ud1 = s->in[I_Z_D], udd1 = s->in[I_Z_DD];
    double zp = (s->z + h * s->zd) + (0.25 * h * h) * s->zdd;
    double zdp = s->zd + (0.5 * h) * s->zdd;
    double rhs = (-(c * zdp) - k * zp) - ((-k) * u1 + (-c) * ud1);
    double a = ((a0 * rhs) / l) / l;
    s->z = zp + (0.25 * h * h) * a;
    s->zd = zdp + (0.5 * h) * a;
    s->zdd = a;
    s->u = u1;
    s->ud = ud1;
    s->udd = udd1;
    s->t = s->t + h;
}

/* Output `i` (FIRST_OUTPUT..) of a model state (LinearVehicle::wheel_force, TrainFmu::refresh). */
static double output_of(const State *s, int i) {
    double k = PAR(s, P_K), c = PAR(s, P_C);
    switch (i) {
    case O_X: return s->x0_t0 + PAR(s, P_SPEED) * s->t;
    case O_VX: return PAR(s, P_SPEED);
    case O_FY: return 0.0;
    case O_MX: return 0.0;
    case O_FZ: return ((s->p0 - k * s->u) - c * s->ud) - (0.0 + ((-k) * s->z + (-c) * s->zd));
    case O_AY: return 0.0;
    case O_AZ: return s->zdd;
    case O_Z: return s->z;
    case O_VZ: return s->zd;
    default: return NAN;
    }
}

static int check_parameter(Instance *inst, int i, double value) {
    const char *why = NULL;
    switch (i) {
    case P_SPEED: if (!(value > 0.0 && value <= MAX_SPEED)) why = "must be > 0 and at most 200 m/s"; break;
    case P_M: if (!(value > 0.0)) why = "must be positive"; break;
    case P_K: if (!(value > 0.0)) why = "must be positive"; break;
    case P_C: if (!(value >= 0.0)) why = "must not be negative"; break;
    default: break;
    }
    if (why) {
        LOG(inst, fmi2Error, "logStatusError", "fmi2SetReal: parameter (value reference %u) = %g %s",
            VR_OF[i], value, why);
        return 0;
    }
    return 1;
}

static int nonempty(fmi2String s) { return s && s[0] != '\0'; }

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
        LOG(inst, fmi2Error, "logStatusError", "wrong GUID %s, expected %s", guid ? guid : "(null)", GUID);
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
    inst->s.stop_defined = stopTimeDefined ? 1 : 0;
    inst->s.stop_time = stopTime;
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
    initialize_model(&inst->s);
    inst->s.phase = STEPPING;
    LOG(inst, fmi2OK, "logEvents", "initialized at t = %g: z = %g m, F_z = %g N", inst->s.time,
        inst->s.z, output_of(&inst->s, O_FZ));
    return fmi2OK;
}

FMI2_Export fmi2Status fmi2Terminate(fmi2Component c) {
    Instance *inst = (Instance *)c;
    if (inst->s.phase != STEPPING && inst->s.phase != FAILED) {
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
    State pre;
    const State *model = &inst->s;
    size_t n;
    if (nvr > 0 && (inst->s.phase == INSTANTIATED || inst->s.phase == INITIALIZATION)) {
        /* not built yet: the outputs of the initial state on the current inputs */
        pre = inst->s;
        initialize_model(&pre);
        model = &pre;
    }
    for (n = 0; n < nvr; n++) {
        int i = index_of(vr[n]);
        if (i < 0) {
            LOG(inst, fmi2Error, "logStatusError", "fmi2GetReal: unknown value reference %u", vr[n]);
            return fmi2Error;
        }
        if (i < N_INPUTS) value[n] = inst->s.in[i];
        else if (i >= FIRST_PARAM) value[n] = PAR(&inst->s, i);
        else value[n] = output_of(model, i);
        if (!isfinite(value[n])) {
            LOG(inst, fmi2Error, "logStatusError", "fmi2GetReal: value reference %u is not finite (%g)",
                vr[n], value[n]);
            return fmi2Error;
        }
    }
    return fmi2OK;
}

FMI2_Export fmi2Status fmi2SetReal(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
                                   const fmi2Real value[]) {
    Instance *inst = (Instance *)c;
    size_t n;
    for (n = 0; n < nvr; n++) {
        int i = index_of(vr[n]);
        if (i < 0 || (i >= FIRST_OUTPUT && i < FIRST_PARAM)) {
            LOG(inst, fmi2Error, "logStatusError", "fmi2SetReal: value reference %u is not an input or parameter", vr[n]);
            return fmi2Error;
        }
        if (!isfinite(value[n])) {
            LOG(inst, fmi2Error, "logStatusError", "fmi2SetReal: value reference %u cannot be set to %g", vr[n], value[n]);
            return fmi2Error;
        }
        if (i >= FIRST_PARAM) {
            if (inst->s.phase != INSTANTIATED && inst->s.phase != INITIALIZATION) {
                LOG(inst, fmi2Error, "logStatusError",
                    "fmi2SetReal: parameter (value reference %u) is fixed after initialisation", vr[n]);
                return fmi2Error;
            }
            if (!check_parameter(inst, i, value[n])) return fmi2Error;
            PAR(&inst->s, i) = value[n];
        } else {
            if (inst->s.phase == TERMINATED) {
                LOG(inst, fmi2Error, "logStatusError", "fmi2SetReal: the FMU is terminated");
                return fmi2Error;
            }
            inst->s.in[i] = value[n];
        }
    }
    return fmi2OK;
}

FMI2_Export fmi2Status fmi2GetInteger(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
                                      fmi2Integer value[]) {
    Instance *inst = (Instance *)c;
    (void)vr; (void)value;
    if (nvr == 0) return fmi2OK;
    LOG(inst, fmi2Error, "logStatusError", "fmi2GetInteger: the FMU has no Integer variables");
    return fmi2Error;
}

FMI2_Export fmi2Status fmi2GetBoolean(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
                                      fmi2Boolean value[]) {
    Instance *inst = (Instance *)c;
    (void)vr; (void)value;
    if (nvr == 0) return fmi2OK;
    LOG(inst, fmi2Error, "logStatusError", "fmi2GetBoolean: the FMU has no Boolean variables");
    return fmi2Error;
}

FMI2_Export fmi2Status fmi2GetString(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
                                     fmi2String value[]) {
    Instance *inst = (Instance *)c;
    (void)vr; (void)value;
    if (nvr == 0) return fmi2OK;
    LOG(inst, fmi2Error, "logStatusError", "fmi2GetString: the FMU has no String variables");
    return fmi2Error;
}

FMI2_Export fmi2Status fmi2SetInteger(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
                                      const fmi2Integer value[]) {
    Instance *inst = (Instance *)c;
    (void)vr; (void)value;
    if (nvr == 0) return fmi2OK;
    LOG(inst, fmi2Error, "logStatusError", "fmi2SetInteger: the FMU has no Integer variables");
    return fmi2Error;
}

FMI2_Export fmi2Status fmi2SetBoolean(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
                                      const fmi2Boolean value[]) {
    Instance *inst = (Instance *)c;
    (void)vr; (void)value;
    if (nvr == 0) return fmi2OK;
    LOG(inst, fmi2Error, "logStatusError", "fmi2SetBoolean: the FMU has no Boolean variables");
    return fmi2Error;
}

FMI2_Export fmi2Status fmi2SetString(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
                                     const fmi2String value[]) {
    Instance *inst = (Instance *)c;
    (void)vr; (void)value;
    if (nvr == 0) return fmi2OK;
    LOG(inst, fmi2Error, "logStatusError", "fmi2SetString: the FMU has no String variables");
    return fmi2Error;
}

FMI2_Export fmi2Status fmi2GetFMUstate(fmi2Component c, fmi2FMUstate *state) {
    Instance *inst = (Instance *)c;
    if (!state) {
        LOG(inst, fmi2Error, "logStatusError", "fmi2GetFMUstate: the FMUstate argument is NULL");
        return fmi2Error;
    }
    if (*state == NULL) {
        *state = malloc(sizeof(State));
        if (*state == NULL) return fmi2Error;
    } else if (((State *)*state)->magic != STATE_MAGIC) {
        LOG(inst, fmi2Error, "logStatusError", "fmi2GetFMUstate: not a state of this FMU");
        return fmi2Error;
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
    if (state && *state) {
        ((State *)*state)->magic = 0;
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
    if (state == NULL || ((State *)state)->magic != STATE_MAGIC || size != sizeof(State)) {
        LOG(inst, fmi2Error, "logStatusError", "fmi2SerializeFMUstate: invalid state or size %zu (expected %zu)",
            size, sizeof(State));
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
    if (inst->s.stop_defined &&
        t + h > inst->s.stop_time + TIME_TOLERANCE * fmax(1.0, fabs(inst->s.stop_time))) {
        LOG(inst, fmi2Error, "logStatusError", "fmi2DoStep: the step from %.17g by %g passes the stop time %.17g",
            t, h, inst->s.stop_time);
        return fmi2Error;
    }
    newmark_step(&inst->s, h);
    if (!(isfinite(inst->s.z) && isfinite(inst->s.zd) && isfinite(inst->s.zdd))) {
        LOG(inst, fmi2Error, "logStatusError", "fmi2DoStep: the vehicle response became non-finite at t = %g", t + h);
        inst->s.phase = FAILED;
        return fmi2Error;
    }
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
