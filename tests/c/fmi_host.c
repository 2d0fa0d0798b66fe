/* See fmi_host.h. */
#define _POSIX_C_SOURCE 200809L
#include "fmi_host.h"

#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#ifndef FMI_STATIC
#include <dlfcn.h>
#endif

static long g_live, g_total, g_live_bytes, g_peak_bytes;

/* each block carries its size in a 16-byte header, so live and peak bytes can be counted */
static void *count_calloc(size_t n, size_t size) {
    size_t bytes = n * size;
    unsigned char *p = (unsigned char *)calloc(1, bytes + 16);
    long live, peak;
    if (!p) return NULL;
    memcpy(p, &bytes, sizeof bytes);
    __atomic_add_fetch(&g_live, 1, __ATOMIC_RELAXED);
    __atomic_add_fetch(&g_total, 1, __ATOMIC_RELAXED);
    live = __atomic_add_fetch(&g_live_bytes, (long)bytes, __ATOMIC_RELAXED);
    peak = __atomic_load_n(&g_peak_bytes, __ATOMIC_RELAXED);
    while (live > peak && !__atomic_compare_exchange_n(&g_peak_bytes, &peak, live, 0, __ATOMIC_RELAXED,
                                                       __ATOMIC_RELAXED)) {
    }
    return p + 16;
}

static void count_free(void *q) {
    unsigned char *p = (unsigned char *)q;
    size_t bytes;
    if (!p) return;
    p -= 16;
    memcpy(&bytes, p, sizeof bytes);
    __atomic_sub_fetch(&g_live, 1, __ATOMIC_RELAXED);
    __atomic_sub_fetch(&g_live_bytes, (long)bytes, __ATOMIC_RELAXED);
    free(p);
}

long host_peak_bytes(void) { return __atomic_load_n(&g_peak_bytes, __ATOMIC_RELAXED); }

long host_live_allocations(void) { return __atomic_load_n(&g_live, __ATOMIC_RELAXED); }
long host_total_allocations(void) { return __atomic_load_n(&g_total, __ATOMIC_RELAXED); }

double host_now(void) {
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static void logger(fmi2ComponentEnvironment envp, fmi2String name, fmi2Status status, fmi2String category,
                   fmi2String message, ...) {
    host_env_t *env = (host_env_t *)envp;
    va_list ap;
    char text[sizeof env->last];
    /* the message is a printf format (the FMU doubles every '%' of its text) */
    va_start(ap, message);
    if (message) vsnprintf(text, sizeof text, message, ap);
    else snprintf(text, sizeof text, "(null message)");
    va_end(ap);
    if (!env) return;
    env->n_msgs++;
    env->n_since_mark++;
    if ((int)status > env->worst) env->worst = (int)status;
    memcpy(env->last, text, sizeof text);
    if (env->echo)
        fprintf(stderr, "[%s] %s status %d: %s\n", name ? name : "(null)", category ? category : "(null)",
                (int)status, text);
}

void host_env_mark(host_env_t *env) {
    env->worst = -1;
    env->n_since_mark = 0;
}

fmi2CallbackFunctions host_callbacks(host_env_t *env) {
    fmi2CallbackFunctions cb;
    cb.logger = logger;
    cb.allocateMemory = count_calloc;
    cb.freeMemory = count_free;
    cb.stepFinished = NULL;
    cb.componentEnvironment = env;
    return cb;
}

#ifdef FMI_STATIC
#define GET(f) api->f = fmi2##f
int fmi_api_load(fmi_api_t *api, const char *so_path, char *err, size_t errlen) {
    (void)so_path; (void)err; (void)errlen;
    memset(api, 0, sizeof *api);
#else
#define GET(f)                                                                               \
    do {                                                                                     \
        *(void **)(&api->f) = dlsym(api->dl, "fmi2" #f);                                     \
        if (!api->f) {                                                                       \
            snprintf(err, errlen, "%s: no symbol fmi2%s", so_path, #f);                      \
            dlclose(api->dl);                                                                \
            api->dl = NULL;                                                                  \
            return -1;                                                                       \
        }                                                                                    \
    } while (0)
int fmi_api_load(fmi_api_t *api, const char *so_path, char *err, size_t errlen) {
    memset(api, 0, sizeof *api);
    if (!so_path) { snprintf(err, errlen, "no shared library given (built without FMI_STATIC)"); return -1; }
    api->dl = dlopen(so_path, RTLD_NOW | RTLD_LOCAL);
    if (!api->dl) { snprintf(err, errlen, "dlopen %s: %s", so_path, dlerror()); return -1; }
#endif
    GET(GetTypesPlatform); GET(GetVersion); GET(SetDebugLogging); GET(Instantiate); GET(FreeInstance);
    GET(SetupExperiment); GET(EnterInitializationMode); GET(ExitInitializationMode); GET(Terminate);
    GET(Reset); GET(GetReal); GET(GetInteger); GET(GetBoolean); GET(GetString); GET(SetReal);
    GET(SetInteger); GET(SetBoolean); GET(SetString); GET(GetFMUstate); GET(SetFMUstate);
    GET(FreeFMUstate); GET(SerializedFMUstateSize); GET(SerializeFMUstate); GET(DeSerializeFMUstate);
    GET(GetDirectionalDerivative); GET(EnterEventMode); GET(NewDiscreteStates);
    GET(EnterContinuousTimeMode); GET(CompletedIntegratorStep); GET(SetTime); GET(SetContinuousStates);
    GET(GetDerivatives); GET(GetEventIndicators); GET(GetContinuousStates);
    GET(GetNominalsOfContinuousStates); GET(SetRealInputDerivatives); GET(GetRealOutputDerivatives);
    GET(DoStep); GET(CancelStep); GET(GetStatus); GET(GetRealStatus); GET(GetIntegerStatus);
    GET(GetBooleanStatus); GET(GetStringStatus);
    return 0;
}

void fmi_api_unload(fmi_api_t *api) {
#ifndef FMI_STATIC
    if (api->dl) dlclose(api->dl);
#endif
    api->dl = NULL;
}
