"""The code layout of docs/layout.md holds: a name without a leading underscore is public or shared.

A module-level name in a public module (one whose dotted path has no ``_``-prefixed part) is either
exported by its package (``__all__``), used by another module of ``redkin``, or one of the few public
names listed here; everything else is an internal and carries a leading underscore.
"""

from __future__ import annotations

import ast
import re
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
PACKAGE = ROOT / "src" / "redkin"

#: Public although no other module uses them: model builders and rotation helpers a user calls directly, the
#: types that appear in public signatures, and the console entry point.
PUBLIC = {
    "redkin.models": {"srs_chain", "kuka_iiwa7", "kuka_iiwa14_table1", "franka_panda", "franka_fr3", "kinova_gen3",
                      "ufactory_xarm7"},
    "redkin.examples": {"FOLDER"},
    "redkin.so3": {"rot_x", "rot_y", "rot_z", "axis_angle_to_matrix", "matrix_to_axis_angle", "matrix_to_xyz_fixed"},
    "redkin.chain": {"Convention"},
    "redkin.arms.registry": {"KINDS"},
    "redkin.arms.classify": {"ArmClass"},
    "redkin.arms.feasible_sets": {"CONTAINS_TOLERANCE"},
    "redkin.closed_form": {"ClosedFormSolutions"},
    "redkin.collision.joint_motion": {"PairLevers"},
    "redkin.cli.main": {"main"},
    "redkin.reproduce": {"SECTION_MODULES"},
    "redkin.srs.feasible": {"LimitTables"},
    "redkin.srs.geometry": {"PsiJointLimits"},
    "redkin.torso_arm.elbow_angle": {"ReferenceKind"},
    "redkin.torso_arm.geometry": {"Side"},
    "redkin.torso_arm.maps": {"DualMeasure", "Region"},
    "redkin.velocity.methods": {"Step"},
    "redkin.virtual_arms.dynamics": {"GainLaw"},
    "redkin.workspace.humanoid": {"HumanoidRun"},
}


def _module_name(path: Path) -> str:
    parts = path.relative_to(PACKAGE.parent).with_suffix("").parts
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


def _top_level_names(tree: ast.Module) -> list[str]:
    names = []
    for node in tree.body:
        if isinstance(node, ast.FunctionDef | ast.ClassDef):
            names.append(node.name)
        elif isinstance(node, ast.Assign):
            names.extend(t.id for t in node.targets if isinstance(t, ast.Name))
        elif isinstance(node, ast.AnnAssign) and isinstance(node.target, ast.Name):
            names.append(node.target.id)
    return names


def _exported(tree: ast.Module) -> set[str]:
    for node in tree.body:
        if isinstance(node, ast.Assign) and any(isinstance(t, ast.Name) and t.id == "__all__" for t in node.targets):
            return {ast.literal_eval(e) for e in node.value.elts}  # type: ignore[attr-defined]
    return set()


SOURCES = {_module_name(p): p.read_text(encoding="utf-8") for p in sorted(PACKAGE.rglob("*.py"))}
TREES = {name: ast.parse(text) for name, text in SOURCES.items()}


def test_a_public_looking_name_is_public_or_shared():
    stray = []
    for module, tree in TREES.items():
        if any(part.startswith("_") for part in module.split(".")):
            continue  # a private module: all of it is internal
        package = module.rsplit(".", 1)[0] if module.count(".") > 1 else "redkin"
        exported = _exported(TREES[package]) if package != module else set()
        others = [text for name, text in SOURCES.items() if name != module]
        for name in _top_level_names(tree):
            if name.startswith("_") or name in exported or name in PUBLIC.get(module, set()):
                continue
            word = re.compile(rf"\b{re.escape(name)}\b")
            if not any(word.search(text) for text in others):
                stray.append(f"{module}.{name}")
    assert not stray, "used only inside their own module, so internal: prefix with '_'\n" + "\n".join(stray)


def test_every_exported_name_exists():
    for module, tree in TREES.items():
        defined = set(_top_level_names(tree))
        for node in ast.walk(tree):
            if isinstance(node, ast.ImportFrom):
                defined.update(alias.asname or alias.name for alias in node.names)
        missing = _exported(tree) - defined - {"__version__"}
        assert not missing, f"{module}.__all__ names what it does not define or import: {sorted(missing)}"
