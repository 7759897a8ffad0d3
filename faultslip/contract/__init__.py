"""The model contract, below everything that consumes it.

A model family declares here what it is: how its scenes are read and varied (:class:`Parameter`,
``with_values``), what it computes (:class:`Output`), its run and simulation, and how a block of
cells is evaluated for a sweep (:class:`Cells`). ``studies/``, ``lab/``, ``evaluation/``, ``apps/``
and ``cli/`` ask this layer and never name a family; a family's own modules register here
(:func:`register`), and :data:`DECLARATIONS` names where each lives, imported on first use, as
entry points name plug-ins.
"""

import importlib

# Loaded on first use (PEP 562): the command line's parser reads faultslip.contract.options without numpy.
_EXPORTS = {"registry": ("DECLARATIONS", "FAMILIES", "SCENE_TYPES", "Declaration", "Family", "declare", "families",
                         "family_of", "family_of_document", "load", "method_rows", "register"),
            "specs": ("Output", "Parameter", "flags_attrs"),
            "options": ("OPTIONS", "Option", "options_of")}
_WHERE = {name: module for module, names in _EXPORTS.items() for name in names}
__all__ = sorted(_WHERE)


def __getattr__(name):
    if name in _WHERE:
        value = getattr(importlib.import_module(f"faultslip.contract.{_WHERE[name]}"), name)
        globals()[name] = value
        return value
    raise AttributeError(f"module 'faultslip.contract' has no attribute {name!r}")
