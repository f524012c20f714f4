"""Helpers of the derivation-cache tests: a forger who knows an entry's layout."""

import numpy as np

from gd_analyze.cache import checksum


def forge(path, fields, **change):
    """Rewrite a cache entry with some arrays changed and a checksum that matches them.

    Parameters
    ----------
    path : pathlib.Path
        The ``.npz`` entry.
    fields : sequence of str
        Its arrays, in the order the checksum covers them.
    **change : ndarray
        The arrays replaced.
    """
    with np.load(path, allow_pickle=False) as z:
        entry = {name: z[name] for name in z.files}
    entry.update(change)
    entry["checksum"] = np.array(checksum(entry, fields))
    with open(path, "wb") as fh:
        np.savez(fh, **entry)
