"""redkin's tests: one ``test_<package>_<module>.py`` per module of ``src/redkin`` (flat), shared pieces in
``support/``.

The tests check what commands print line by line, so the one-time notice that kernels are being compiled
(:data:`redkin._compiled.COMPILE_NOTICE`) is turned off here, before redkin is imported, for this process and the
ones it starts; ``tests/test_compile_notice.py`` turns it back on where it is the subject.
"""

import os

os.environ["REDKIN_COMPILE_NOTICE"] = "0"
