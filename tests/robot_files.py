"""Robot files the tests write: the shipped ones with something taken out."""


def toml_without_limits(folder):
    """The shipped two-link.toml without its position, velocity and acceleration limits.

    Parameters
    ----------
    folder : pathlib.Path
        Where to write ``free.toml``.

    Returns
    -------
    pathlib.Path
        The file written.
    """
    from importlib import resources

    text = resources.files("gd_analyze").joinpath("data", "two-link.toml").read_text()
    kept = [line for line in text.splitlines()
            if not line.startswith(("q_limits_deg", "qd_max_deg", "qdd_max_deg"))]
    assert len(kept) == len(text.splitlines()) - 6
    path = folder / "free.toml"
    path.write_text("\n".join(kept) + "\n")
    return path
