/*
 * Variadic fmi2CallbackLogger for the fmi-export harness.
 *
 * componentEnvironment must point to a `fmi_export_log_env` (defined on the Rust side as
 * `#[repr(C)] struct LogEnv { sink, context }`). The message is formatted with vsnprintf
 * (heap buffer when it does not fit on the stack) and handed to `sink` as a plain
 * NUL-terminated string. A NULL environment or sink drops the message.
 */
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>

typedef void (*fmi_export_log_sink)(void *context, const char *instance_name, int status,
                                    const char *category, const char *message);

typedef struct {
    fmi_export_log_sink sink;
    void *context;
} fmi_export_log_env;

void fmi_export_harness_logger(void *component_environment, const char *instance_name,
                               int status, const char *category, const char *format, ...) {
    fmi_export_log_env *env = (fmi_export_log_env *)component_environment;
    char stack_buffer[1024];
    char *message = stack_buffer;
    char *heap_buffer = NULL;
    va_list args;
    int needed;

    if (env == NULL || env->sink == NULL) {
        return;
    }
    if (format == NULL) {
        env->sink(env->context, instance_name, status, category, "(NULL format)");
        return;
    }

    va_start(args, format);
    needed = vsnprintf(stack_buffer, sizeof stack_buffer, format, args);
    va_end(args);

    if (needed < 0) {
        message = "(message could not be formatted)";
    } else if ((size_t)needed >= sizeof stack_buffer) {
        heap_buffer = (char *)malloc((size_t)needed + 1);
        if (heap_buffer != NULL) {
            va_start(args, format);
            vsnprintf(heap_buffer, (size_t)needed + 1, format, args);
            va_end(args);
            message = heap_buffer;
        }
        /* on allocation failure the truncated stack copy is delivered */
    }

    env->sink(env->context, instance_name, status, category, message);
    free(heap_buffer);
}
