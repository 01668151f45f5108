"""Settings for the whole test session."""

import signal


def pytest_configure(config):
    """A suite started in the background by a script (``pytest ... &``) inherits SIGINT
    ignored, and so would every command the tests start (an ignored signal stays ignored
    across exec): the interrupt tests would then see Ctrl-C do nothing.  Give the session
    Python's own handler back; the processes it starts then get the default action."""
    if signal.getsignal(signal.SIGINT) is signal.SIG_IGN:
        signal.signal(signal.SIGINT, signal.default_int_handler)
