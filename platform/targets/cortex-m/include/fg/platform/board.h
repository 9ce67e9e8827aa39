/* Board hooks of the Cortex-M platform (platform/targets/cortex-m). The platform library
 * defines each one weak; a firmware overrides it by defining a function of the same
 * name (C linkage). Plain C so a C firmware can include it. */
#ifndef FG_PLATFORM_BOARD_H
#define FG_PLATFORM_BOARD_H

#ifdef __cplusplus
extern "C" {
#endif

/* Writes one diagnostic line (null-terminated, ending in '\n'): a UART, an RTT buffer,
 * the firmware's log. Called from the planner's context: it must not block for long.
 * Default: ARM semihosting SYS_WRITE0 when built with FG_SEMIHOSTING (a debugger or
 * QEMU must be attached, else the BKPT faults), otherwise nothing. */
void fg_board_log(const char* line);

/* A broken invariant (a bug, never bad input): file, line, the failed condition.
 * Default: logs the line through fg_board_log; then with FG_SEMIHOSTING ends the
 * session with a failure status, otherwise halts in debug builds and returns in
 * release builds (the planner then reports Status::internal_error). */
void fg_board_fault(const char* file, int line, const char* what);

#ifdef __cplusplus
}
#endif

#endif
