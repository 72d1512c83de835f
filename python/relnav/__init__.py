"""relnav — spacecraft relative navigation from Python.

* :class:`Estimator` — one of the library's filters (EKF, UKF, AQUKF, five particle
  filters, robust H-infinity) with the FMU's parameters as keyword arguments and the
  library's step semantics; ``run`` steps through numpy arrays in one call.
* :func:`campaign` — the evaluation engine's Monte Carlo campaigns on local threads or a
  Dask cluster, bit-identical to ``relnav simulate``.
* :func:`parameters` — the FMU's parameter table (names, types, units, defaults).
* :mod:`relnav.errors` — the library's errors, one class per C-ABI status code.

Example (paper 000's set-up is the default)::

    import relnav
    est = relnav.Estimator(filter="ukf")
    est.step([0.0, 0.0, 0.0], [670.8204, 0.896055, 0.302746], dt=1.0)
    print(est.state, est.sigma)
"""

from __future__ import annotations

from typing import Any, Dict, List

from . import errors
from ._campaign import campaign, scenario_text
from ._relnav import CampaignResult, Estimator, __version__
from ._relnav import builtin_scenarios as _builtin_scenarios
from ._relnav import parameters_table as _parameters_table
from .errors import (
    Error,
    InfeasibleError,
    InvalidArgumentError,
    NotImplementedError,
    NullPointerError,
    NumericalError,
    PanicError,
)

__all__ = [
    "Estimator",
    "CampaignResult",
    "campaign",
    "scenario_text",
    "parameters",
    "scenarios",
    "errors",
    "Error",
    "NullPointerError",
    "InvalidArgumentError",
    "NotImplementedError",
    "NumericalError",
    "PanicError",
    "InfeasibleError",
    "__version__",
]


def parameters() -> List[Dict[str, Any]]:
    """The Estimator's keyword arguments: the FMU's parameters, from the same variable
    table as ``modelDescription.xml``. One dict per parameter with ``name``,
    ``value_reference``, ``type`` (``Real``, ``Integer`` or ``Boolean``, as in the FMU),
    ``unit``, ``default`` (a code parameter's item name), ``description`` and, for the
    code parameters (``filter``, ``frame``, ...), ``items`` as (name, code, description)."""
    return _parameters_table()


def scenarios() -> List[str]:
    """Names of the built-in scenarios (the papers' examples) that :func:`campaign`
    accepts by name."""
    return _builtin_scenarios()
