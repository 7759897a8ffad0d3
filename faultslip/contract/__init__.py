"""The model contract, below everything that consumes it.

A model family declares here what it is: how its scenes are read and varied (:class:`Parameter`,
``with_values``), what it computes (:class:`Output`), its run and simulation, and how a block of
cells is evaluated for a sweep (:class:`Cells`). ``studies/``, ``lab/``, ``evaluation/``, ``apps/``
and ``cli/`` ask this layer and never name a family; a family's own modules register here
(:func:`register`), and :data:`DECLARATIONS` names where each lives, imported on first use, as
entry points name plug-ins.
"""

from faultslip.contract.registry import (DECLARATIONS, FAMILIES, SCENE_TYPES, Declaration, Family, declare,
                                         families, family_of, family_of_document, load, method_rows, register)
from faultslip.contract.specs import Output, Parameter, flags_attrs

__all__ = ["DECLARATIONS", "Declaration", "FAMILIES", "Family", "Output", "Parameter", "SCENE_TYPES", "declare",
           "families", "family_of", "family_of_document", "flags_attrs", "load", "method_rows", "register"]
