# SPDX-License-Identifier: GPL-3.0-or-later
"""The skeleton of every long operator (Paint, Paint Animation, Render Comparison): the whole job at once
headless, modal with a progress bar, a status text and Esc interactively.

Headless (``blender -b``) no timer ever fires, so ``invoke()`` hands over to
``execute()``, which does the whole job. Interactively, ``invoke()`` calls
the operator's ``begin_modal()``, which checks the job and calls
``start_timer()``; each timer event then calls its ``step()`` and Esc its
``escape()``; ``end_modal()`` takes the timer, the progress bar and the
status text away. The painter's own work runs in a ``Worker`` thread that
never touches bpy data; headless, the same work's ``Outcome`` is reported
the same way.
"""

import threading

import bpy

TIMER_INTERVAL = 0.1
"""Seconds between a modal operator's timer events."""


class ModalJob:
    """What a long operator adds to ``bpy.types.Operator``. The operator defines ``execute(context)`` (the
    whole job), ``begin_modal(context)`` (checks, ``start_timer``; returns the operator's result),
    ``step(context)`` (one timer event) and may end in ``end_modal``. Esc calls ``escape(context)``, which by
    default asks the operator's ``_worker`` to stop; ``step`` then reports how it ended."""

    timer_interval = TIMER_INTERVAL
    status_title = "Paint Relief"

    def invoke(self, context, event):
        if bpy.app.background:
            return self.execute(context)
        return self.begin_modal(context)

    def modal(self, context, event):
        if event.type == "ESC" and event.value == "PRESS":
            return self.escape(context)
        if event.type != "TIMER":
            return {"PASS_THROUGH"}
        return self.step(context)

    def escape(self, context):
        """Esc: ask the ``_worker`` to stop and keep running until it has."""
        self._worker.cancel.set()
        return {"RUNNING_MODAL"}

    def start_timer(self, context):
        """Start the timer whose events reach ``modal``, the progress bar and the modal handler."""
        wm = context.window_manager
        self._timer = wm.event_timer_add(self.timer_interval, window=context.window)
        wm.progress_begin(0, 100)
        wm.modal_handler_add(self)

    def show(self, context, fraction, text, percent=True):
        """The progress bar at ``fraction`` in [0, 1] and the status text "<title>: <percent>% <text>" (without
        the percent when ``percent`` is False)."""
        context.window_manager.progress_update(int(100 * fraction))
        shown = "{:.0f}% {}".format(100 * fraction, text) if percent else text
        context.workspace.status_text_set("{}: {}".format(self.status_title, shown))

    def end_modal(self, context):
        """Remove the timer and the progress bar (when they were started) and the status text."""
        wm = context.window_manager
        if getattr(self, "_timer", None) is not None:
            wm.event_timer_remove(self._timer)
            self._timer = None
            wm.progress_end()
        context.workspace.status_text_set(None)

    def show_worker(self, context):
        """While the operator's ``_worker`` (a ``Worker``) runs, show its progress, or that it is cancelling, and
        return True; False once it has ended."""
        worker = self._worker
        if not worker.is_alive():
            return False
        if worker.cancel.is_set():
            self.show(context, worker.fraction, "cancelling...", percent=False)
        else:
            self.show(context, worker.fraction, "{} (Esc to cancel)".format(worker.message))
        return True

    def report_outcome(self, outcome, finish, warn):
        """Report how the work ended (an ``Outcome``): its error (a WARNING when ``warn``, else an ERROR) and
        CANCELLED, or ``finish(result)`` and FINISHED."""
        if outcome.error is not None:
            self.report({"WARNING"} if warn else {"ERROR"}, outcome.error)
            return {"CANCELLED"}
        finish(outcome.result)
        return {"FINISHED"}


class Outcome:
    """How ``work(progress, cancel)`` ended: its ``result``, or the one sentence it failed with (``error``) and
    whether it ``stopped`` because it was asked to (``core.Cancelled``)."""

    def __init__(self):
        self.result = self.error = None
        self.stopped = False

    def run(self, work, failure, progress=None, cancel=None, sentences=()):
        """Run ``work``; keep its result or its error: the message of core's errors and of ``sentences`` (more
        exception classes whose messages are sentences) as it stands, ``failure(error)`` for any other."""
        from .. import core

        try:
            self.result = work(progress, cancel)
        except core.Cancelled as stopped:
            self.error, self.stopped = str(stopped), True
        except (core.PaintReliefError, *sentences) as error:
            self.error = str(error)
        except Exception as error:  # an unexpected failure still reaches the user as one line
            self.error = failure(error)
        return self


class Worker(Outcome):
    """``work(progress, cancel)`` in a thread of its own (``Outcome``), its latest progress and the event that
    asks it to stop (``cancel``, a ``threading.Event`` of its own unless given)."""

    def __init__(self, work, failure, name="paint_relief", cancel=None):
        super().__init__()
        self.cancel = cancel if cancel is not None else threading.Event()
        self.fraction, self.message = 0.0, "Starting"
        self._thread = threading.Thread(target=self.run, args=(work, failure, self.progress, self.cancel.is_set),
                                        name=name, daemon=True)
        self._thread.start()

    def progress(self, fraction, message):
        self.fraction, self.message = fraction, message

    def is_alive(self):
        return self._thread.is_alive()

    def stop(self):
        """Ask the work to stop and wait until it has."""
        self.cancel.set()
        self._thread.join()
