"""cli/__init__.py: while a command runs, the cyclic garbage collector leaves what existed
before it alone (frozen) and collects generation 0 less often; both are set back after it,
whatever the command did, and a freeze made by the caller is left as it was."""

import gc

import pytest

import gd_analyze.cli as cli


@pytest.fixture
def collector():
    """The collector's settings put back after the test, whatever it did."""
    before = gc.get_threshold()
    yield
    gc.set_threshold(*before)
    gc.unfreeze()


def _recording(seen, result=0):
    def command(args):
        seen.append((gc.get_threshold(), gc.get_freeze_count()))
        if isinstance(result, Exception):
            raise result
        return result
    return command


@pytest.mark.parametrize("outcome", [0, RuntimeError("boom")])
def test_a_command_runs_with_the_collector_tuned_and_it_is_set_back(monkeypatch, collector,
                                                                    outcome):
    seen = []
    monkeypatch.setattr(cli, "cmd_plan", _recording(seen, outcome))
    gc.set_threshold(701, 11, 12)
    assert gc.get_freeze_count() == 0
    objects = len(gc.get_objects())
    code = cli.main(["plan", "two-link", "-o", "unused.csv"])
    assert code == (0 if outcome == 0 else 4)
    (threshold, frozen), = seen
    assert threshold[0] == 10_000 and threshold[1:] == (10, 10)
    assert frozen >= objects // 2            # what existed before: out of the collections
    assert gc.get_threshold() == (701, 11, 12)
    assert gc.get_freeze_count() == 0


def test_a_freeze_made_before_is_left_as_it_was(monkeypatch, collector):
    seen = []
    monkeypatch.setattr(cli, "cmd_plan", _recording(seen))
    gc.freeze()
    frozen = gc.get_freeze_count()
    assert frozen > 0
    assert cli.main(["plan", "two-link", "-o", "unused.csv"]) == 0
    assert seen[0][1] == frozen and seen[0][0][0] == 10_000
    assert gc.get_freeze_count() == frozen
