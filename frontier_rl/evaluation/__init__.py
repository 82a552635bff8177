"""Paired experiments: configuration, runners and backends, results folders, statistics, plots and reports."""

from frontier_rl.evaluation.report.table import table_4_1
from frontier_rl.evaluation.statistics.paired import PairedStats, compare_methods, paired_stats

__all__ = ["PairedStats", "compare_methods", "paired_stats", "table_4_1"]
