"""The derivation cache as the store of the model building: certifications and searches.

The model building (:mod:`gd_analyze.simplify.deploy`) is pure and keeps nothing between runs
itself; the jobs give it :data:`DERIVATIONS`, which reads and writes the region's
certification (:func:`.certification_cache.certification`, each entry checked before it is
used) and the searches under it (:func:`.certification_cache.read_search`,
:func:`.certification_cache.write_search`), and notes each certification, and each model whose
bound was proved, for the checks of a model file built in the same process
(:func:`.model_trust.remember`, :func:`.model_trust.remember_claim`).
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

from ..cache import entry_path
from ..simplify.region_memo import Derivations
from .certification_cache import certification, read_search, search_key, write_search
from .model_trust import remember, remember_claim

if TYPE_CHECKING:
    from ..certify.region import Region
    from ..model.robot import Robot

__all__ = ["DERIVATIONS"]


def _read(robot: Robot, region: Region, tolerance: float, torque_floor: float, samples: int,
          n: int, b: int, screened: bool = False) -> tuple[Any, str]:
    key = search_key(robot, region, tolerance, torque_floor, samples, screened)
    return read_search(key, n, b), str(entry_path(key))


#: The derivation cache (:mod:`gd_analyze.cache`; off with ``GD_ANALYZE_NO_CACHE``).
DERIVATIONS = Derivations(certification=certification, read_search=_read,
                          write_search=write_search, made=remember, claimed=remember_claim)
