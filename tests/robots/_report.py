"""Reading a check report's JSON: its findings of one severity."""

from __future__ import annotations


def sev(report: dict, severity: str) -> list:
    """The findings of ``severity`` ("error", "warning", "note") in a report or link dict."""
    return [f for f in report["findings"] if f["severity"] == severity]
