"""redkin's tests: one ``test_<package>_<module>.py`` per module of ``src/redkin`` (flat), shared pieces in
``support/``.

The tests check what commands print line by line, so the notice and the progress lines said while kernels compile
(:data:`redkin._compiled.COMPILE_NOTICE`) are turned off here, before redkin is imported, for this process and the
ones it starts; ``tests/test_compile_notice.py`` turns them back on where they are the subject.  So is the
background compile a command starts where it ran as Python on a fresh cache (:mod:`redkin.cli.background_compile`):
processes left running would load the machine under later tests; ``tests/test_cli_background_compile.py`` turns it
on where it is the subject.
"""

import os

os.environ["REDKIN_COMPILE_NOTICE"] = "0"
os.environ["REDKIN_BACKGROUND_COMPILE"] = "0"
