"""Test-suite settings: a derandomized hypothesis profile under CI (the ``CI`` environment
variable), so that the property and fuzz suites cost the same and find the same on every
run, and the fuzz suite's table of outcomes at the end of the run."""

import os

from hypothesis import settings

settings.register_profile("ci", derandomize=True, print_blob=True)
if os.environ.get("CI"):
    settings.load_profile("ci")


def pytest_terminal_summary(terminalreporter):
    from test_fuzz import OUTCOMES

    if not OUTCOMES:
        return
    columns = ["typed error", "valid result", "callback re-raised", "other"]
    terminalreporter.section("fuzz outcomes")
    terminalreporter.write_line(f"{'target':28s} {'tried':>6s} " + " ".join(f"{c:>18s}" for c in columns))
    total = dict.fromkeys(columns, 0)
    for target, counts in sorted(OUTCOMES.items()):
        tried = sum(counts.values())
        terminalreporter.write_line(
            f"{target:28s} {tried:6d} " + " ".join(f"{counts[c]:18d}" for c in columns)
        )
        for c in columns:
            total[c] += counts[c]
    terminalreporter.write_line(
        f"{'all':28s} {sum(total.values()):6d} " + " ".join(f"{total[c]:18d}" for c in columns)
    )
