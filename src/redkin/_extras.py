"""The one message for an optional extra that is not installed, with the command for either kind of install."""

from __future__ import annotations


def missing_extra(need: str, extra: str) -> str:
    """The line saying that ``need`` (what the user asked for, and the packages it takes) comes with the extra
    ``extra``, and how to install it: ``pip install "redkin[EXTRA]"`` for an installed redkin, and
    ``pip install -e ".[EXTRA]"`` in a checkout of redkin's repository (where the first would fetch redkin from the
    package index instead).

    ``missing_extra("reading an MJCF file needs mujoco", "mjcf")`` is ``'reading an MJCF file needs mujoco, in the
    mjcf extra: pip install "redkin[mjcf]" (in a checkout of redkin: pip install -e ".[mjcf]")'``.
    """
    return (f'{need}, in the {extra} extra: pip install "redkin[{extra}]" '
            f'(in a checkout of redkin: pip install -e ".[{extra}]")')
