"""The redundancy parameter of a class of arm (the arm angle psi, q7) and the words it is printed in."""

from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True)
class Parameter:
    """The redundancy parameter of a class of arm, and its words.

    Attributes
    ----------
    name : str
        ``"psi"`` (the arm angle, [000 eq. 6]) or ``"q7"`` (the value of joint 7, docs/franka.md): as the command
        line's options and JSON name it.
    domain : tuple of float
        The values it takes, radians: ``(-pi, pi)`` for the arm angle, joint 7's range for q7.
    wraps : bool
        Whether it is an angle on the circle (``domain``'s ends are one value).
    noun, plural : str
        The parameter in words: ``"arm angle"``, ``"arm angles"``; ``"q7"``, ``"values of q7"``.
    symbol, set_symbol, set_ascii : str
        The parameter and its feasible set in print: ``"ψ"``, ``"Ψ"`` and ``"Psi"`` (plain text); ``"q7"``,
        ``"Q7"``, ``"Q7"``.
    prefix : str
        The parameter in a name: ``"arm-angle"`` (the ``arm-angle explorer``, a map's ``arm-angle_...``
        attributes), ``"q7"``.
    joint_symbol : str
        The symbol of the joint values (``"θ"`` in paper 000, ``"q"``).
    branch_signs : str
        What a branch's three signs are.
    equation : str
        Where the feasible set is defined (a citation).
    optimum : str
        Where the limit-avoiding value is defined (a citation).
    """

    name: str
    domain: tuple[float, float]
    wraps: bool
    noun: str
    plural: str
    symbol: str
    set_symbol: str
    set_ascii: str
    prefix: str
    joint_symbol: str
    branch_signs: str
    equation: str
    optimum: str
