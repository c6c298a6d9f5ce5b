"""Reading the runs of the study scripts: a run's evaluation.json, and index files whose lines end
with a run folder, grouped by some of their fields (shared by pan_table.py, rates_table.py and
coring_table.py), and when a run counts as tracked (dso_table.py)."""
import json
from collections import OrderedDict
from pathlib import Path


def evaluation(run, name="evaluation.json"):
    """The run's evaluation.json (or another of its evaluations), or None when it could not be evaluated."""
    try:
        return json.loads(Path(run, name).read_text())
    except (OSError, ValueError):
        return None


def grouped_evaluations(index, key):
    """Index lines `FIELD... RUN` grouped by key(fields), in file order: key -> list of
    evaluations (None for a run that failed)."""
    groups = OrderedDict()
    for line in Path(index).read_text().splitlines():
        fields = line.split()
        if fields:
            groups.setdefault(key(fields), []).append(evaluation(fields[-1]))
    return groups


TRACKED_ATE_SHARE = 0.005  # of the path length
TRACKED_POSED_SHARE = 0.95  # of the frames


def tracked(e):
    """A run counts as tracked (issue 41's rule) when it posed at least 95 % of the frames and its
    Sim(3)-aligned ATE is at most 0.5 % of the path; a run that could not be evaluated (e None)
    is not."""
    return e is not None and e["coverage"] >= TRACKED_POSED_SHARE and e["ate_relative"] <= TRACKED_ATE_SHARE
