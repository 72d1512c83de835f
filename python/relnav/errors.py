"""The library's errors as Python exceptions, one class per status code of the C ABI
(``relnav_status`` in ``include/relnav.h``). Each carries the library's message and its
``status`` code, and also derives from the matching built-in exception, so
``except ValueError`` catches a bad argument as usual.

=====================  ======  =====================================================
class                  status  raised when
=====================  ======  =====================================================
Error                  —       base class of all below
NullPointerError       1       (C ABI only: a null pointer; never raised by Python)
InvalidArgumentError   2       a parameter or input is out of its domain, has the
                               wrong type or name, an array the wrong shape; also
                               a bad scenario of ``relnav.campaign``
NotImplementedError    3       the filter is not available in this build
NumericalError         4       the filter could not complete the step
PanicError             5       an internal panic (a bug in relnav; please report it)
InfeasibleError        6       (H-infinity design without solution; C ABI only so far)
InvalidStateError      8       a saved state that is truncated, corrupted or foreign
=====================  ======  =====================================================
"""

from __future__ import annotations

import builtins

__all__ = [
    "Error",
    "NullPointerError",
    "InvalidArgumentError",
    "NotImplementedError",
    "NumericalError",
    "PanicError",
    "InfeasibleError",
    "InvalidStateError",
]


class Error(Exception):
    """Base class of relnav's errors; ``status`` is the C ABI's status code."""

    status: int = -1


class NullPointerError(Error):
    """``RELNAV_ERROR_NULL_POINTER`` (1): a required pointer was null (C ABI only)."""

    status = 1


class InvalidArgumentError(Error, ValueError):
    """``RELNAV_ERROR_INVALID_ARGUMENT`` (2): an argument is out of its domain."""

    status = 2


class NotImplementedError(Error, builtins.NotImplementedError):  # noqa: A001 (mirrors the status name)
    """``RELNAV_ERROR_NOT_IMPLEMENTED`` (3): the filter is not implemented in this build."""

    status = 3


class NumericalError(Error, ArithmeticError):
    """``RELNAV_ERROR_NUMERICAL`` (4): the filter could not complete the step (zero range,
    loss of positive definiteness, every particle weight zero)."""

    status = 4


class PanicError(Error, RuntimeError):
    """``RELNAV_ERROR_PANIC`` (5): a Rust panic was caught (a bug in relnav)."""

    status = 5


class InfeasibleError(Error, ArithmeticError):
    """``RELNAV_ERROR_INFEASIBLE`` (6): the H-infinity design has no solution."""

    status = 6


class InvalidStateError(Error, ValueError):
    """``RELNAV_ERROR_INVALID_STATE`` (8): a saved state that is truncated, corrupted, of
    another format version or of another configuration."""

    status = 8
