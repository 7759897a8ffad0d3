"""What a solution method would do for a problem: the common record of every method's assessment."""

from __future__ import annotations

import math
from dataclasses import dataclass, field


@dataclass
class Assessment:
    """What a method would do for a scene: applicable or not, why, its error and cost estimates."""

    method: str
    applicable: bool
    reason: str
    estimated_error: float = math.inf
    estimated_cost: float = math.inf
    settings: dict = field(default_factory=dict)
