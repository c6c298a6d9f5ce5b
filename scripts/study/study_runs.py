"""Reading the runs of the study scripts: a run's evaluation.json, and index files whose lines end
with a run folder, grouped by some of their fields (shared by pan_table.py, rates_table.py and
coring_table.py)."""
import json
from collections import OrderedDict
from pathlib import Path


def evaluation(run):
    """The run's evaluation.json, or None when it could not be evaluated."""
    try:
        return json.loads(Path(run, "evaluation.json").read_text())
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
