"""The built-in material library: steels, MR fluids, copper, air, with sources and trust levels.

``list()`` is ``mrbrake materials list --json``; ``get(name)`` returns a :class:`Material` whose
curves are NumPy arrays (H in A/m, B in T, yield stress in Pa) and whose ``to_dict()`` is
``mrbrake materials show NAME --json``.
"""

from . import _native
from ._native import Material

__all__ = ["Material", "get", "list"]


def list():  # noqa: A001  (the module's public name, as in the CLI)
    """Every built-in material: ``{"default_fluid": str, "materials": [{"name", "kind", "trust",
    "description"}, ...]}`` (the JSON of ``mrbrake materials list --json``)."""
    return _native.materials_list()


def get(name):
    """The material ``name`` (case-insensitive, e.g. ``"steel-1008"``, ``"mrf-122eg"``).

    Raises ``ValueError`` for an unknown name (the message lists the known ones)."""
    return _native.materials_get(name)
