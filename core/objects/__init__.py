"""Several objects' textures painted side by side, each as ``core.paint_object`` paints it alone.

``jobs``: a job (``paint_object``'s arguments) checked, and handed over to
another process as files. ``worker``: the entry point of such a process,
``python -m core.objects.worker``. ``side_by_side``: ``paint_objects``, which
keeps what an earlier run painted, runs the worker processes on the machine's
cores and gathers their reports, progress and failures.
"""
