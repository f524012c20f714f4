"""A full disk or an HDF5 error while writing is one line (exit 2); a bug is not."""

import errno

import pytest

from gd_analyze.errors import InputError
from gd_analyze.store.staging import writing


def _close_after_enospc():
    """What h5py's close raises after a write failed with ENOSPC: another error, chained."""
    try:
        raise OSError(errno.ENOSPC, "No space left on device")
    except OSError:
        raise AttributeError("'FileIO' object has no attribute 'truncate'") from None


def _close_after_enospc_in_context():
    try:
        raise OSError(errno.ENOSPC, "No space left on device")
    except OSError:
        raise AttributeError("flush failed")      # noqa: B904 - the context is the point


def _in_h5py():
    exec(compile("raise RuntimeError(\"Can't decrement id ref count\")",
                 "/site-packages/h5py/_hl/files.py", "exec"))


@pytest.mark.parametrize("fail, expect", [
    (_close_after_enospc_in_context, "out: cannot write the output folder: no space left on the "
                                     "device"),
    (_in_h5py, "out: cannot write the output folder: HDF5 error: Can't decrement id ref count")])
def test_write_failures_are_one_line(fail, expect):
    with pytest.raises(InputError) as err:
        with writing("out"):
            fail()
    assert str(err.value) == expect


@pytest.mark.parametrize("error", [RuntimeError("a bug"), ValueError("a bug"),
                                   KeyError("a bug")])
def test_other_errors_are_not_write_errors(error):
    with pytest.raises(type(error)):
        with writing("out"):
            raise error


def test_an_enospc_under_raise_from_none_is_still_found():
    """``raise ... from None`` keeps the context for the traceback: it is still found."""
    with pytest.raises(InputError, match="no space left on the device"):
        with writing("out"):
            _close_after_enospc()
