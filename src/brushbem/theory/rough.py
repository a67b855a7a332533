"""Rough brush closed forms (thesis ch. 5): the fitted adhesion coefficient (eq. 5.8).

The rough brush's force and displacement scales are the rigid brush's
(:mod:`brushbem.theory.brush`, eq. 5.3-5.4).
"""

from __future__ import annotations

from ._common import _nonnegative, _out, _positive

__all__ = [
    "adhesion_coefficient",
    "critical_roughness",
]


# ---------------------------------------------------------------------------
# Rough brushes: adhesion coefficient at small preload (eq. 5.8)
# ---------------------------------------------------------------------------


def adhesion_coefficient(normalized_roughness, alpha, beta):
    """Adhesion coefficient of a rough brush at small preload, ``c = alpha / sigma~ - beta`` (eq. 5.8).

    ``F~_A = c F~_P`` in the linear region.  The fit is not clipped: ``c <= 0``
    (``sigma~ >= alpha / beta``) means no macroscopic adhesion.

    Parameters
    ----------
    normalized_roughness : float or array_like
        sigma~ = sigma / |d_c| (eq. 5.5), dimensionless; positive.
    alpha : float or array_like
        Fitted amplification factor alpha(k~) (Table 1), dimensionless; positive.
    beta : float or array_like
        Fitted bias beta(k~) (Table 1), dimensionless; non-negative.

    Returns
    -------
    float or ndarray
        c, dimensionless.
    """
    sigma = _positive("normalized_roughness", normalized_roughness)
    a = _positive("alpha", alpha)
    b = _nonnegative("beta", beta)
    return _out(a / sigma - b)


def critical_roughness(alpha, beta):
    """Roughness at which the fitted adhesion coefficient vanishes, ``sigma~_c = alpha / beta``.

    Parameters
    ----------
    alpha : float or array_like
        Fitted amplification factor, dimensionless; positive.
    beta : float or array_like
        Fitted bias, dimensionless; positive.

    Returns
    -------
    float or ndarray
        sigma~_c, dimensionless.
    """
    a = _positive("alpha", alpha)
    b = _positive("beta", beta)
    return _out(a / b)
