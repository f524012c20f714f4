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


def erd_path(path):
    """A file of example-robot-data's robots folder, as a string.

    Parameters
    ----------
    path : str
        Relative to ``robots``, e.g. ``kinova_description/robots/kinova.urdf``.

    Returns
    -------
    str
    """
    import importlib.metadata

    root = importlib.metadata.distribution("example-robot-data").locate_file(
        "cmeel.prefix/share/example-robot-data/robots")
    return str(root / path)


#: Arms of the inertia proof's tests: (built-in name or URDF path, tip or None).
INERTIA_ARMS = {"panda": ("panda", None),
                "erd-panda": (erd_path("panda_description/urdf/panda.urdf"), "panda_hand"),
                "kinova": (erd_path("kinova_description/robots/kinova.urdf"), None),
                "puma560": ("puma560", None)}


def inertia_arm(key):
    """The robot of :data:`INERTIA_ARMS` ``key``."""
    from gd_analyze import load_robot

    path, tip = INERTIA_ARMS[key]
    return load_robot(path, tip=tip) if tip else load_robot(path)


def crba(robot, q):
    """Pinocchio's joint-space inertia matrix at each position, both triangles filled.

    Parameters
    ----------
    robot : Robot
    q : ndarray, shape (N, n)

    Returns
    -------
    ndarray, shape (N, n, n)
    """
    import numpy as np
    import pinocchio as pin

    from gd_analyze.dynamics.pinocchio import pinocchio_model

    pm = pinocchio_model(robot)
    data = pm.createData()
    D = np.array([pin.crba(pm, data, x) for x in q])
    return np.triu(D) + np.swapaxes(np.triu(D, 1), 1, 2)


def random_chain(n, seed=0, prismatic=True):
    """A random chain of n joints with a joint-limit region: general placements, every third
    joint prismatic (none without ``prismatic``), limits of +-2.5 rad and +-0.3 m, 2 rad/s,
    4 rad/s^2 (the chains of analysis/scaling.py).

    Parameters
    ----------
    n : int
    seed : int, optional
    prismatic : bool, optional

    Returns
    -------
    Robot
    """
    import numpy as np
    from scipy.spatial.transform import Rotation

    from gd_analyze.model.robot_spec import robot_from_chain

    rng = np.random.default_rng(seed)
    joints = []
    for i in range(n):
        B = rng.normal(size=(3, 3)) * 0.1
        S = B @ B.T
        slides = prismatic and i % 3 == 2
        lim = 0.3 if slides else 2.5
        joints.append({
            "type": "prismatic" if slides else "revolute",
            "rotation": Rotation.random(random_state=seed * 1000 + i).as_matrix(),
            "translation": rng.uniform(-0.3, 0.3, 3), "mass": rng.uniform(0.3, 4.0),
            "com": rng.uniform(-0.2, 0.2, 3), "inertia": np.trace(S) * np.eye(3) - S,
            "q_min": -lim, "q_max": lim, "qd_max": 2.0, "qdd_max": 4.0})
    return robot_from_chain(f"random-{n}", joints, [0.0, 0.0, -9.81])


def chain_toml(n, limits=True, last_qd_max=True):
    """The robot file (TOML text) of an n-joint arm: parallel joint axes but for a twist of
    90 deg at joint n - 1 (its explicit model derives in seconds at n = 10); with ``limits``,
    joint limits of +-170 deg; without ``last_qd_max``, no velocity limit on joint n (no
    joint-limit region); 180 deg/s and 360 deg/s^2 otherwise."""
    lines = [f'name = "chain-{n}"', "gravity = [0.0, -9.8062, 0.0]", ""]
    for k in range(n):
        length, mass = 0.3 - 0.01 * k, 2.0 - 0.1 * k
        inertia = mass * length**2 / 12
        twist = k == n - 2
        lines += ["[[link]]", f"d = {0.05 if twist else 0.0}", f"a = {length!r}",
                  f"alpha_deg = {90.0 if twist else 0.0}", "offset_deg = 0.0", f"mass = {mass!r}",
                  f"com = [{-length / 2!r}, 0.01, 0.005]",
                  f"inertia = [0.002, {inertia!r}, {inertia!r}, 0.0001, 0.0, 0.0]",
                  *(["q_limits_deg = [-170.0, 170.0]"] if limits else []),
                  *(["qd_max_deg = 180.0"] if last_qd_max or k < n - 1 else []),
                  "qdd_max_deg = 360.0", ""]
    return "\n".join(lines)
