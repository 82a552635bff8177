"""Paired statistics of exploration times: every method against a baseline on the same episodes.

The thesis compared two methods over 120 paired episodes with a one-tailed paired t-test and
reported episodes above 1000 s and 2000 s as outliers; this module does that for any number of
methods, adds the Wilcoxon signed-rank test and a confidence interval of the mean saving, and
lays the result out like the thesis's Table 4.1.
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy import stats

from frontier_rl.errors import ConfigError

THESIS_OUTLIERS_S = (1000.0, 2000.0)
"""The thesis's outlier thresholds (s): episodes above them left out of a comparison."""


@dataclass(frozen=True)
class PairedStats:
    """One method against the baseline, on the episodes both ran.

    Attributes:
        n: number of paired episodes.
        mean_time_s, var_time_s: the method's mean and sample variance (ddof 1) of exploration time (s, s²).
        mean_diff_s: mean of baseline − method (s): positive means the method is faster.
        ci95_s: 95 % confidence interval of ``mean_diff_s`` (Student's t), (low, high).
        p_one_tailed: paired t-test that the method is faster (its mean time is lower).
        p_two_tailed: paired t-test of any difference.
        p_wilcoxon: Wilcoxon signed-rank test, one-tailed in the same direction.
        reduction_pct: 100 × mean_diff / baseline mean.
    """

    n: int
    mean_time_s: float
    var_time_s: float
    mean_diff_s: float
    ci95_s: tuple[float, float]
    p_one_tailed: float
    p_two_tailed: float
    p_wilcoxon: float
    reduction_pct: float


def paired_stats(times: ArrayLike, baseline: ArrayLike) -> PairedStats:
    """Statistics of ``times`` against ``baseline`` (s), paired by position."""
    t = np.asarray(times, dtype=np.float64)
    b = np.asarray(baseline, dtype=np.float64)
    if t.shape != b.shape or t.ndim != 1:
        raise ConfigError(f"paired times need two 1-D arrays of one length, got shapes {t.shape} and {b.shape}")
    n = len(t)
    if n == 0:
        nan = math.nan
        return PairedStats(0, nan, nan, nan, (nan, nan), nan, nan, nan, nan)
    diff = b - t
    mean_diff = float(diff.mean())
    var = float(t.var(ddof=1)) if n > 1 else math.nan
    if n > 1:
        half = float(stats.t.ppf(0.975, n - 1) * diff.std(ddof=1) / math.sqrt(n))
        ci = (mean_diff - half, mean_diff + half)
    else:
        ci = (math.nan, math.nan)
    p_one, p_two, p_wil = _tests(t, b)
    base_mean = float(b.mean())
    reduction = 100.0 * mean_diff / base_mean if base_mean else math.nan
    return PairedStats(n, float(t.mean()), var, mean_diff, ci, p_one, p_two, p_wil, reduction)


def _tests(t: NDArray[np.float64], b: NDArray[np.float64]) -> tuple[float, float, float]:
    """One- and two-tailed paired t-tests and the one-tailed Wilcoxon test; NaN where undefined
    (fewer than two pairs; all differences zero)."""
    if len(t) < 2 or np.all(t == b):
        return math.nan, math.nan, math.nan
    with warnings.catch_warnings():
        # constant or tied differences: scipy warns (and falls back to an approximation or returns 0 or 1)
        warnings.simplefilter("ignore")
        p_one = float(stats.ttest_rel(t, b, alternative="less").pvalue)
        p_two = float(stats.ttest_rel(t, b).pvalue)
        p_wil = float(stats.wilcoxon(t, b, alternative="less").pvalue)
    return p_one, p_two, p_wil


def compare_methods(
    times: Mapping[str, ArrayLike], baseline: str, outlier_above_s: float | None = None
) -> dict[str, PairedStats]:
    """Every method of ``times`` (name → times per episode, aligned) against ``baseline``.

    With ``outlier_above_s``, an episode is left out of a method's comparison when the method's or
    the baseline's time in it is above the threshold (s), as the thesis did at 1000 s and 2000 s;
    the baseline's own row thus drops only its own outliers. An episode whose time is NaN (a team
    whose robots all failed: no time to explore) is left out so too, always.
    """
    if baseline not in times:
        raise ConfigError(f"baseline {baseline!r} is not among the methods {sorted(times)}")
    if outlier_above_s is not None and not outlier_above_s > 0:
        raise ConfigError(f"outlier threshold must be a positive number of seconds, got {outlier_above_s!r}")
    base = np.asarray(times[baseline], dtype=np.float64)
    out = {}
    for name, values in times.items():
        t = np.asarray(values, dtype=np.float64)
        if t.shape != base.shape:
            raise ConfigError(f"method {name!r} has {t.size} episodes, the baseline {base.size}")
        keep = np.isfinite(t) & np.isfinite(base)
        if outlier_above_s is not None:
            keep &= (t <= outlier_above_s) & (base <= outlier_above_s)
        out[name] = paired_stats(t[keep], base[keep])
    return out


def holm_adjust(p_values: Mapping[str, float | None], family_size: int = 0) -> dict[str, float | None]:
    """Holm's step-down adjustment of a family of p-values (name → p; None stays None): the i-th
    smallest of m becomes max over j ≤ i of min(1, (m − j + 1)·p_j). m counts the defined p-values,
    or ``family_size`` when that is larger: the hypotheses tested whose p is undefined (a method
    whose times equal the baseline's in every episode) still count, as p = 1 would.
    A method is significant at level a (0.05, say) after the adjustment when its adjusted p is below a; the
    family-wise error rate is then at most a, whatever the dependence between the tests."""
    present = sorted((float(p), name) for name, p in p_values.items() if p is not None and math.isfinite(p))
    m = max(len(present), family_size)
    adjusted: dict[str, float | None] = {name: None for name in p_values}
    running = 0.0
    for rank, (p, name) in enumerate(present):
        running = max(running, min(1.0, (m - rank) * p))
        adjusted[name] = running
    return adjusted
