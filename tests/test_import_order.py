"""Every module of redkin imports first, in a fresh set of modules: no import cycle depends on which module a user
(or a command) happens to import first.  A cycle between ``numerical._kernels`` and the ``srs`` package once broke
``redkin explore`` while the suite, importing in another order, passed."""

import subprocess
import sys
from pathlib import Path

SOURCE = Path(__file__).resolve().parents[1] / "src" / "redkin"

SCRIPT = """
import importlib, sys
failures = []
for name in sys.argv[1:]:
    for loaded in [key for key in sys.modules if key == "redkin" or key.startswith("redkin.")]:
        del sys.modules[loaded]
    try:
        importlib.import_module(name)
    except ImportError as error:
        failures.append(f"{name}: {error}")
print("\\n".join(failures))
"""


def module_names() -> list[str]:
    names = []
    for path in sorted(SOURCE.rglob("*.py")):
        parts = path.relative_to(SOURCE.parent).with_suffix("").parts
        names.append(".".join(parts[:-1] if parts[-1] == "__init__" else parts))
    return names


def test_every_module_imports_first():
    names = module_names()
    assert "redkin.numerical._kernels" in names and "redkin.srs.nearly" in names
    result = subprocess.run([sys.executable, "-c", SCRIPT, *names], capture_output=True, text=True, timeout=600,
                            env={"REDKIN_COMPILE_NOTICE": "0", "PATH": "", "MPLBACKEND": "Agg",
                                 "PYTHONPATH": str(SOURCE.parent)})
    assert result.returncode == 0, result.stderr[-2000:]
    assert result.stdout.strip() == "", result.stdout
