"""``python -m core``: the painter's command line.

SIGINT and SIGTERM are caught from the first moment: while the command line
and its array libraries load (up to a second), nothing has been written yet,
so a signal then ends the process with one sentence and 128 + the signal's
number. The command line installs its own handlers once loaded.
"""

import os
import signal
import sys

_NAMES = {signal.SIGINT: "SIGINT", signal.SIGTERM: "SIGTERM"}


def _stopped_while_starting(signum, frame):
    sentence = f"Stopped by {_NAMES[signum]} while starting; nothing was written and every folder was left as it was."
    os.write(2, f"paint-relief: {sentence}\n".encode())
    os._exit(128 + signum)


for _signum in _NAMES:
    signal.signal(_signum, _stopped_while_starting)

from .cli import main  # noqa: E402 (after the handlers, so a signal during these imports is caught)

sys.exit(main())
