/* walker._hybrid's interrupts: SIGINT and SIGTERM stop compiled work within a step.
 *
 * The compiled loops run without the GIL, where Python cannot run its signal handlers
 * (PyErr_CheckSignals needs the GIL and the main thread).  So while any compiled call runs,
 * a C-level handler is installed for SIGINT and SIGTERM.  It does two async-signal-safe
 * things: it sets the flag wk_interrupt (hybrid.h), which every compiled loop polls (the
 * step loop each step), and it hands the signal on to the handler it replaced, normally
 * CPython's own, which records it for the Python-level handler (KeyboardInterrupt, or the
 * command line's), or, for a signal whose action was the default one, restores that
 * action and raises the signal again, so the process ends exactly as it would have.  A
 * signal whose action is "ignore" is left alone.
 *
 * Installation and removal happen with the GIL held (wkpy_signals_begin before releasing
 * it, wkpy_signals_end after taking it back), counted, so threads running compiled calls
 * at the same time share one installation: the first installs, the last removes (and only
 * when the handler is still its own: one installed meanwhile is kept).  The flag is cleared
 * when the first call starts; once set, it stops every compiled call of the process until
 * the last one has ended, which is what an interrupt asks for.
 *
 * Without POSIX sigaction (Windows) nothing is installed and the flag stays 0: compiled
 * calls then run to their budgets, as before.
 */
#define PY_SSIZE_T_CLEAN
#include <Python.h>

#include <signal.h>
#include <string.h>

#include "_hybridbinding.h"
#include "hybrid.h"

#if defined(__unix__) || defined(__APPLE__)
#define WKPY_SIGACTION 1
#endif

static int active = 0; /* compiled calls running (changed under the GIL only) */

#ifdef WKPY_SIGACTION
static const int SIGNALS[2] = {SIGINT, SIGTERM};
static struct sigaction previous[2];
static int installed[2];

static void on_signal(int signum, siginfo_t *info, void *context)
{
    wk_interrupt = (sig_atomic_t)signum;
    for (int i = 0; i < 2; i++) {
        if (SIGNALS[i] != signum) continue;
        const struct sigaction *prev = &previous[i];
        if (prev->sa_flags & SA_SIGINFO) {
            prev->sa_sigaction(signum, info, context);
        } else if (prev->sa_handler == SIG_DFL) {
            /* the default action (terminate): as if this handler had never been there */
            sigaction(signum, prev, NULL);
            raise(signum);
        } else if (prev->sa_handler != SIG_IGN) {
            prev->sa_handler(signum);
        }
    }
}
#endif

void wkpy_signals_begin(void)
{
    if (active++ > 0) return;
    wk_interrupt = 0;
#ifdef WKPY_SIGACTION
    for (int i = 0; i < 2; i++) {
        installed[i] = 0;
        struct sigaction now;
        if (sigaction(SIGNALS[i], NULL, &now) != 0) continue;
        if (!(now.sa_flags & SA_SIGINFO) && now.sa_handler == SIG_IGN) continue;
        struct sigaction mine;
        memset(&mine, 0, sizeof mine);
        mine.sa_sigaction = on_signal;
        mine.sa_flags = SA_SIGINFO | SA_ONSTACK;
        sigemptyset(&mine.sa_mask);
        previous[i] = now;
        if (sigaction(SIGNALS[i], &mine, NULL) == 0) installed[i] = 1;
    }
#endif
}

int wkpy_signals_end(void)
{
    const int interrupted = wk_interrupt != 0;
    if (--active == 0) {
#ifdef WKPY_SIGACTION
        for (int i = 0; i < 2; i++) {
            if (!installed[i]) continue;
            struct sigaction now;
            if (sigaction(SIGNALS[i], NULL, &now) == 0 && (now.sa_flags & SA_SIGINFO) &&
                now.sa_sigaction == on_signal)
                sigaction(SIGNALS[i], &previous[i], NULL);
            installed[i] = 0;
        }
#endif
    }
    return interrupted;
}

/* The thread that imported the module: the main one (where Python runs its handlers). */
static unsigned long main_thread = 0;

void wkpy_signals_init(void)
{
    main_thread = PyThread_get_thread_ident();
}

int wkpy_interrupted(int must_raise)
{
    if (PyErr_CheckSignals() < 0) return -1; /* the Python handler raised (main thread) */
    if (!must_raise && PyThread_get_thread_ident() == main_thread) return 0;
    PyErr_SetString(PyExc_KeyboardInterrupt, "a signal interrupted the compiled computation");
    return -1;
}
