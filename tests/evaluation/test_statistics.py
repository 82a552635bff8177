"""Paired statistics against hand-computed values and scipy's."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy import stats

from frontier_rl.errors import ConfigError
from frontier_rl.evaluation import compare_methods, paired_stats, table_4_1
from frontier_rl.evaluation.report.table import p_value
from frontier_rl.evaluation.results.summary import PairedSummary
from frontier_rl.evaluation.statistics.paired import holm_adjust

BASE = [10.0, 12.0, 14.0, 16.0]
FAST = [9.0, 11.0, 12.0, 15.0]  # savings 1, 1, 2, 1


def test_hand_computed_values() -> None:
    s = paired_stats(FAST, BASE)
    assert s.n == 4
    assert s.mean_time_s == pytest.approx(11.75)
    assert s.var_time_s == pytest.approx(np.var(FAST, ddof=1))
    assert s.mean_diff_s == pytest.approx(1.25)
    # sd of the savings 0.5, so t = 1.25 / (0.5 / 2) = 5 with 3 degrees of freedom
    half = 3.182446305284263 * 0.5 / 2
    assert s.ci95_s == pytest.approx((1.25 - half, 1.25 + half))
    assert s.p_one_tailed == pytest.approx(0.0076965, rel=1e-4)  # P(T3 > 5)
    assert s.p_two_tailed == pytest.approx(2 * 0.0076965, rel=1e-4)
    assert s.reduction_pct == pytest.approx(100 * 1.25 / 13.0)


def test_matches_scipy_on_random_pairs() -> None:
    rng = np.random.default_rng(0)
    base = rng.uniform(300, 900, 60)
    method = base * rng.normal(0.93, 0.1, 60)
    s = paired_stats(method, base)
    assert s.p_one_tailed == pytest.approx(stats.ttest_rel(method, base, alternative="less").pvalue)
    assert s.p_two_tailed == pytest.approx(stats.ttest_rel(method, base).pvalue)
    assert s.p_wilcoxon == pytest.approx(stats.wilcoxon(method, base, alternative="less").pvalue)
    lo, hi = stats.t.interval(0.95, 59, loc=np.mean(base - method), scale=stats.sem(base - method))
    assert s.ci95_s == pytest.approx((lo, hi))


def test_slower_method_has_a_large_one_tailed_p() -> None:
    s = paired_stats(BASE, FAST)
    assert s.mean_diff_s < 0 and s.p_one_tailed > 0.99 and s.reduction_pct < 0


def test_degenerate_inputs_give_nan_not_errors() -> None:
    same = paired_stats(BASE, BASE)
    assert same.mean_diff_s == 0 and math.isnan(same.p_one_tailed) and math.isnan(same.p_wilcoxon)
    one = paired_stats([5.0], [6.0])
    assert one.n == 1 and math.isnan(one.ci95_s[0]) and math.isnan(one.var_time_s)
    assert paired_stats([], []).n == 0
    assert PairedSummary.values_of(one)["ci95_s"] == (None, None)
    with pytest.raises(ConfigError, match="shapes"):
        paired_stats([1.0, 2.0], [1.0])


def test_outliers_are_dropped_pairwise() -> None:
    times = {"base": [100.0, 1500.0, 300.0, 400.0], "m": [90.0, 200.0, 2500.0, 350.0]}
    everything = compare_methods(times, "base")
    assert everything["m"].n == 4
    trimmed = compare_methods(times, "base", outlier_above_s=1000.0)
    assert trimmed["m"].n == 2 and trimmed["base"].n == 3  # the baseline row drops only its own outliers
    assert trimmed["m"].mean_diff_s == pytest.approx(30.0)
    with pytest.raises(ConfigError, match="-5"):
        compare_methods(times, "base", outlier_above_s=-5)
    with pytest.raises(ConfigError, match="nope"):
        compare_methods(times, "nope")
    with pytest.raises(ConfigError, match="3 episodes"):
        compare_methods({"base": [1.0, 2.0], "m": [1.0, 2.0, 3.0]}, "base")


def test_table_4_1_layout() -> None:
    results = compare_methods({"fixed:0.75": BASE, "learned": FAST}, "fixed:0.75")
    table = table_4_1(results, "fixed:0.75", title="office, 4 episodes").markdown()
    lines = table.strip().splitlines()
    assert lines[0] == "**office, 4 episodes**"
    assert lines[2].startswith("| method | n | mean time (s) | variance (s²) | sd (s) | mean saving (s)")
    assert lines[4].startswith("| fixed:0.75 (baseline) | 4 | 13.0 | 6.7 | 2.6 |")  # var of 10..16: 20 / 3
    assert lines[5].startswith("| learned | 4 | 11.8 |") and "9.6 %" in lines[5]


def test_holm_adjustment_by_hand() -> None:
    # sorted 0.01, 0.02, 0.04 of m = 3: 3 × 0.01 = 0.03, max(0.03, 2 × 0.02) = 0.04, max(0.04, 1 × 0.04) = 0.04
    adjusted = holm_adjust({"a": 0.04, "b": 0.01, "c": 0.02, "baseline": None})
    assert adjusted["baseline"] is None
    assert adjusted["a"] == pytest.approx(0.04) and adjusted["b"] == pytest.approx(0.03)
    assert adjusted["c"] == pytest.approx(0.04)
    # monotone and capped at 1
    capped = holm_adjust({"x": 0.6, "y": 0.5})
    assert capped == {"x": 1.0, "y": 1.0}
    assert holm_adjust({"only": 0.2}) == {"only": 0.2}
    assert holm_adjust({"nan": math.nan, "p": 0.1}) == {"nan": None, "p": 0.1}


def test_holm_counts_a_tested_hypothesis_whose_p_is_undefined() -> None:
    # two methods tested, one with no defined p (its times equal the baseline's): m is 2, not 1
    assert holm_adjust({"same": None, "p": 0.02}, family_size=2) == {"same": None, "p": 0.04}
    assert holm_adjust({"a": 0.01, "b": 0.02}, family_size=1) == pytest.approx({"a": 0.02, "b": 0.02})


@pytest.mark.parametrize(
    ("p", "text"),
    [(0.0123, "0.012"), (1.5e-7, "1.5e-07"), (0.5, "0.5"), (0.05, "0.05"), (0.0496, "0.0496"), (0.0504, "0.0504"),
     (0.04996, "0.04996"), (None, "n/a"), (math.nan, "n/a")],
)  # fmt: skip
def test_a_p_value_never_rounds_onto_the_significance_level(p: float | None, text: str) -> None:
    assert p_value(p) == text
