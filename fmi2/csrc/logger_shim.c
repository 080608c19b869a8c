/*
 * The fmi2CallbackLogger handed to FMUs.
 *
 * fmi2CallbackLogger is variadic (printf-style), and stable Rust cannot define a variadic
 * function. This shim expands the message with vsnprintf and forwards the finished text
 * to a non-variadic callback. The FMU passes back the fmi2ComponentEnvironment given at
 * fmi2Instantiate; the importer makes it point at a fmi2_log_env, whose `forward`
 * function and `sink` pointer are owned by the Rust side and outlive the instance.
 */
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>

typedef void (*fmi2_log_forward_fn)(void *sink, const char *instance_name, int status,
                                    const char *category, const char *message);

typedef struct {
    fmi2_log_forward_fn forward;
    void *sink;
} fmi2_log_env;

/* Messages longer than this are cut (with a marker) rather than allocated without bound. */
#define FMI2_MAX_MESSAGE (1024 * 1024)

void fmi2_shim_logger(void *component_environment, const char *instance_name, int status,
                     const char *category, const char *message, ...) {
    const fmi2_log_env *env = (const fmi2_log_env *)component_environment;
    char stack_buffer[1024];
    char *heap_buffer = NULL;
    const char *text = stack_buffer;
    va_list args;
    va_list args_copy;
    int needed;

    if (env == NULL || env->forward == NULL) {
        return;
    }
    if (message == NULL) {
        env->forward(env->sink, instance_name, status, category, NULL);
        return;
    }

    va_start(args, message);
    va_copy(args_copy, args);
    needed = vsnprintf(stack_buffer, sizeof stack_buffer, message, args);
    va_end(args);

    if (needed < 0) {
        /* Encoding error in the format: hand over the unexpanded format string. */
        text = message;
    } else if ((size_t)needed >= sizeof stack_buffer) {
        size_t size = (size_t)needed + 1;
        if (size > FMI2_MAX_MESSAGE) {
            size = FMI2_MAX_MESSAGE;
        }
        heap_buffer = (char *)malloc(size);
        if (heap_buffer != NULL) {
            vsnprintf(heap_buffer, size, message, args_copy);
            text = heap_buffer;
        }
        /* If malloc failed, the truncated stack copy is forwarded. */
    }
    va_end(args_copy);

    env->forward(env->sink, instance_name, status, category, text);
    free(heap_buffer);
}
