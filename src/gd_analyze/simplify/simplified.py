"""The simplified model as a value: its robot, its form, what it keeps, its guarantee and cost.

A :class:`SimplifiedModel` is of one of two forms:

- explicit: the kept terms of the explicit G-D model (:mod:`gd_analyze.symbolic.explicit`), pruned
  by the error budget (:mod:`gd_analyze.simplify.budget`) or chosen per element by the chapter's
  rule (:mod:`gd_analyze.simplify.choices`, Sec. 3.4.1), compiled to straight-line code
  (:mod:`gd_analyze.symbolic.codegen`) and printed as C or Python
  (:mod:`gd_analyze.symbolic.emit`);
- recursive: the customized recursive Newton-Euler model on the base parameters with parts of
  their contributions dropped (:mod:`gd_analyze.symbolic.recursive_model`).

It is written as JSON (``simplified_model.json``) that carries its robot's parameters and what
the model keeps, so ``gd_analyze.load_model(path).torque(q, qd, qdd)`` works on any machine
(:mod:`gd_analyze.store.model_file` reads and writes the file).
"""

from __future__ import annotations

import json
from collections.abc import Mapping
from dataclasses import dataclass, field, replace
from functools import cached_property
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike

from ..certify.positive_definite import inertia_statement
from ..errors import InputError
from ..model.kinematics import as_states
from ..model.mounting import mounting_of
from ..ranking.labels import element_labels
from ..symbolic.codegen import build_program
from ..symbolic.drive_regressor import with_drives
from ..symbolic.emit import python_function, state_function
from ..symbolic.emit_model import render
from ..symbolic.explicit import Term, derive, model_terms
from ..symbolic.model_functions import explicit_functions, recursive_functions
from ..symbolic.recursive_model import RecursiveModel
from ..symbolic.safe_text import c_prefix, comment_safe
from .budget import chosen_terms
from .choices import CHOICES, choice_masks, full_choices, merge_choices, simplified_torque  # noqa: F401
from .consistency import check_program
from .guarantee import Guarantee
from .torque_error import TorqueErrorAccumulator, torque_error  # noqa: F401 (re-exported)

if TYPE_CHECKING:
    from ..model.robot import Robot
    from ..symbolic.codegen import Program
    from ..symbolic.model_functions import ModelFunctions

__all__ = ["SCHEMA_VERSION", "CHOICES", "SimplifiedModel", "choice_masks", "merge_choices",
           "full_choices",
           "simplified_torque", "torque_error", "TorqueErrorAccumulator", "parameters_sha256",
           "json_safe", "total_operations"]

#: Version of the simplified_model.json layout (2: explicit terms, rule, tolerance, cost).
SCHEMA_VERSION = 2
#: Older layouts still read (their model is rebuilt from the choices, without pruning).
READABLE_SCHEMAS = (1, 2)
#: The stem of the main job's emitted files (``simplified_model.h``, ``.c``, ...).
SOURCE_STEM = "simplified_model"


def _units(robot):
    """The units line of the emitted files (prismatic joints in m and N)."""
    pris = [i + 1 for i, p in enumerate(getattr(robot, "prismatic", ())) if p]
    text = "q [rad], qd [rad/s], qdd [rad/s^2], tau [N m]"
    if pris:
        joints = ", ".join(str(i) for i in pris)
        text += (f"; prismatic joint{'s' if len(pris) > 1 else ''} {joints}: q [m], qd [m/s], "
                 "qdd [m/s^2], tau [N]")
    return text


def _rounded_up(value):
    """A bound in three significant digits, rounded up so that it still bounds.

    >>> _rounded_up(1.8145e-05), _rounded_up(0.005), _rounded_up(0.0)
    ('1.82e-05', '0.005', '0')
    """
    v = float(value)
    if not (np.isfinite(v) and v > 0):
        return f"{v:g}"
    step = 10.0 ** (np.floor(np.log10(v)) - 2)
    up = np.ceil(v / step * (1 - 1e-12)) * step
    return f"{up:.3g}" if float(f"{up:.3g}") >= v else f"{np.nextafter(up, np.inf):.4g}"


@dataclass(frozen=True, eq=False)
class SimplifiedModel:
    """A simplified G-D model: a robot and a choice per element of D and h.

    Attributes
    ----------
    robot : Robot
        The arm, with n joints.
    choices : dict
        Element label -> ``"tran"``, ``"rot"``, ``"both"`` or ``"none"``; for the recursive
        form ``"both"``, or ``"pruned"`` where its dropped pairs change the element (as
        results.h5 stores it).
    dominance_threshold : float
        s used for the ranking.
    negligible_threshold : float
        e used for the ranking.
    trajectory_sha256 : str
        SHA-256 of the trajectory file the model was derived on.
    validation : dict
        The torque error along that trajectory, as :func:`torque_error` gives it.
    provenance : dict
        Tool version, input file names, settings.
    rule : str
        ``"budget"`` (error budget) or ``"chapter"`` (share-based classes).
    tolerance : float
        EPS of the budget (NaN when not applicable).
    torque_floor : float
        TAU [N m], the least scale of a joint torque.
    terms : Term or None
        The explicit model's kept terms (:mod:`gd_analyze.symbolic.explicit`); None for a model
        read from a layout without them (its kept parts are used, unpruned).
    cost : dict
        Counted operations of the emitted code: multiplications, additions, sin, cos.
    full_cost : dict
        The same for the full explicit model.
    bound : list of float
        Guaranteed bound on |tau_s - tau| per joint on the trajectory [N m] (NaN for the
        chapter rule).
    recursive : RecursiveModel or None
        For a model of the recursive form, the pruned customized recursive
        Newton-Euler model (:class:`~gd_analyze.symbolic.recursive_model.RecursiveModel`);
        None for the explicit form.
    costs : dict
        Counted operations of the other models, by label (``"exact recursive"``,
        ``"explicit, budget"``, ``"explicit, full"``, ``"newton-euler"``), for comparison.
    guarantee : Guarantee or None
        Where the bound holds (:class:`~gd_analyze.simplify.guarantee.Guarantee`):
        over the joint-limit region (proved) or on the trajectory only; None for the chapter
        rule (a file of the budget rule without one is refused).
    program_cache : Program or None
        The model's program where its builder already has it (not written to the file);
        otherwise :meth:`program` builds it once, on first use.
    inertia_check : dict or None
        Whether D_s is proved positive definite where the bound holds
        (:func:`~gd_analyze.certify.positive_definite.with_inertia_check`); None when
        not checked, and for a model read from a file (a stored claim is not believed: it is
        proved again where it is stated).
    functions_cache : ModelFunctions or None
        As ``program_cache``, for :meth:`functions`.
    choice_cache : tuple or None
        Of the recursive form, where its builder already has them: the program without the
        drives and the pairs it leaves out
        (:meth:`gd_analyze.symbolic.recursive_model.RecursiveModel.choice`), so that
        :meth:`functions` does not build them again; a third item, where built, is the exact
        recursive program it was compared with.

    Notes
    -----
    Source: Sec. 3.4.1 of Fu, Gonzalez & Lee (1987): "The less dominant terms or elements can
    be neglected in calculating the dynamic equations of motion of the manipulator."
    """

    robot: Robot
    choices: dict
    dominance_threshold: float
    negligible_threshold: float
    trajectory_sha256: str = ""
    validation: dict = field(default_factory=dict)
    provenance: dict = field(default_factory=dict)
    rule: str = "chapter"
    tolerance: float = float("nan")
    torque_floor: float = 0.0
    terms: Term | None = None
    cost: dict = field(default_factory=dict)
    full_cost: dict = field(default_factory=dict)
    bound: list = field(default_factory=list)
    recursive: RecursiveModel | None = None
    costs: dict = field(default_factory=dict)
    guarantee: Guarantee | None = None
    program_cache: Program | None = field(default=None, repr=False, compare=False)
    inertia_check: dict | None = None
    functions_cache: ModelFunctions | None = field(default=None, repr=False, compare=False)
    choice_cache: tuple | None = field(default=None, repr=False, compare=False)

    @property
    def form(self) -> str:
        """``"recursive"`` or ``"explicit"``: how the emitted code computes tau."""
        return "explicit" if self.recursive is None else "recursive"

    def explicit_terms(self) -> Term:
        """The kept terms of the explicit model (:class:`~gd_analyze.symbolic.explicit.Term`).

        A model read from a layout without terms gets the terms of its kept parts, unpruned.
        """
        return self.terms if self.terms is not None else self._chosen_terms

    @cached_property
    def _chosen_terms(self):
        all_terms = model_terms(derive(self.robot))
        return all_terms.subset(chosen_terms(all_terms, self.choices))

    def program(self) -> Program:
        """The straight-line program of the model
        (:class:`~gd_analyze.symbolic.codegen.Program`), with the drives' armature and
        friction, never dropped (:func:`~gd_analyze.symbolic.drive_regressor.with_drives`)."""
        return self._program

    @cached_property
    def _program(self):
        if self.program_cache is not None:
            return self.program_cache

        if self.recursive is not None:
            return with_drives(self._choice[0], self.robot)

        return with_drives(build_program(self.explicit_terms(), self.robot.n,
                                         np.zeros(self.robot.n),
                                         prismatic=self.robot.prismatic), self.robot)

    def header(self) -> dict:
        """The header of the emitted files: robot, SHA-256s, rule, tolerance, counts, version.

        Returns
        -------
        dict
            The robot's name (input text) only as
            :func:`~gd_analyze.symbolic.safe_text.comment_safe` gives it, with the SHA-256 of the
            raw name; then the SHA-256 of the robot file; the exact recursive model's count where
            ``costs`` holds it, and for a sweep's model of a trajectory guarantee
            (``validation["relative_bound"]``) its bound on each swept trajectory relative to
            that trajectory's scale_i (a region model's bound is in its guarantee line).
        """
        cost = self.cost or self.program().cost()
        exact = self.costs.get("exact recursive")
        compared = {} if not exact else {"exact recursive model": (
            f"{exact['multiplications']} multiplications, {exact['additions']} additions")}
        relative = self.validation.get("relative_bound") if self.validation else None
        if self.guarantee is not None and self.guarantee.proved:
            relative = None             # the region's bound: the guarantee line says it
        if relative:                    # a sweep's model: the bound on each swept trajectory
            compared["bound on each swept trajectory"] = (
                "|tau_s,i - tau_i| <= b_i x scale_i (that trajectory's max(peak |tau_i|, "
                "torque floor)), b = "
                + ", ".join(_rounded_up(v) for v in relative))
        return {
            "gd-analyze simplified model": (
                "tau = D_s qdd + h_s + c (Fu, Gonzalez & Lee 1987, Eq. 3.4-24), explicit form"
                if self.recursive is None else
                "tau = Y_b beta, customized recursive Newton-Euler on base parameters (Fu, "
                "Gonzalez & Lee 1987, Algorithm 3.1; Khalil & Kleinfinger 1987)"),
            "robot": comment_safe(self.robot.name, digest=True),
            "robot file sha256": self.robot.sha256,
            "rule": self.rule, "tolerance": f"{self.tolerance:g}",
            "torque floor [N m]": f"{self.torque_floor:g}",
            "trajectory sha256": self.trajectory_sha256,
            "guarantee": self.scope(),
            **self._region_header(),
            "operations": f"{cost['multiplications']} multiplications, {cost['additions']} "
                          f"additions, {cost['sin']} sin, {cost['cos']} cos",
            **compared,
            **({} if not self.inertia_check else {
                "inertia matrix D_s": inertia_statement(self.inertia_check)}),
            "gd-analyze version": self.provenance.get("gd_analyze_version", ""),
            "units": _units(self.robot),
        }

    def _region_header(self):
        """The guarantee's region as header lines: ``region q [deg]``, ``qd max [deg/s]``,
        ``qdd max [deg/s^2]`` (:meth:`gd_analyze.certify.region.Region.lines`)."""
        region = None if self.guarantee is None else self.guarantee.region
        if region is None:
            return {}
        return {f"region {label}": text for label, text in region.parts()}

    def functions(self) -> ModelFunctions:
        """The deployed model's five functions (tau, D_s, h_s, c_s, Y_s) as programs.

        Returns
        -------
        gd_analyze.symbolic.model_functions.ModelFunctions
            Built once, from the same kept terms as :meth:`program`: D_s qdd + h_s + c_s =
            tau_s and Y_s beta_s = tau_s (:mod:`gd_analyze.symbolic.model_functions`).
        """
        return self._functions

    @cached_property
    def _functions(self):
        if self.functions_cache is not None:
            return self.functions_cache
        if self.recursive is None:
            return explicit_functions(self.robot, self.explicit_terms(), self.program())
        return recursive_functions(self.robot, self.recursive.base(self.robot),
                                   self._choice[1], self.program())

    @cached_property
    def _choice(self):
        """(program, pairs it leaves out) of the recursive form, built once."""
        if self.choice_cache is not None:
            return self.choice_cache
        return self.recursive.choice(self.robot)

    def left_out(self) -> np.ndarray:
        """The (base parameter, part) pairs the deployed program leaves out, recursive form.

        Returns
        -------
        ndarray of bool, shape (b, 3)
            ``recursive.dropped``, or none where the exact program is the cheaper one
            (:meth:`gd_analyze.symbolic.recursive_model.RecursiveModel.choice`).

        Raises
        ------
        ValueError
            For a model of the explicit form.
        """
        if self.recursive is None:
            raise ValueError("an explicit model has no base-parameter pairs")
        return np.asarray(self._choice[1], bool)

    def with_inertia_check(self, check: dict) -> SimplifiedModel:
        """The model with an ``inertia_check``, its program and functions built once.

        Parameters
        ----------
        check : dict
            As :func:`~gd_analyze.certify.positive_definite.with_inertia_check` makes it.

        Returns
        -------
        SimplifiedModel
        """
        return replace(self, inertia_check=check, program_cache=self.program(),
                       functions_cache=self.functions())

    def sources(self, stem: str = SOURCE_STEM, prefix: str | None = None) -> dict:
        """The emitted files' texts (:data:`gd_analyze.symbolic.emit_model.ARTEFACTS`).

        Parameters
        ----------
        stem : str, optional
            ``simplified_model`` (main job) or ``merged_model`` (sweep).
        prefix : str, optional
            Of the C symbols and CasADi functions, a C identifier; default the robot's name
            made one (:func:`~gd_analyze.symbolic.safe_text.c_prefix`).

        Returns
        -------
        dict
            File name -> text: ``STEM.h``, ``STEM.c``, ``STEM.py``, ``STEM_casadi.py``.

        Raises
        ------
        ValueError
            If the prefix is not a C identifier.
        """

        prefix = c_prefix(self.robot.name) if prefix is None else prefix
        return render(self.functions(), self.header(), prefix, stem)

    def _python_tau(self):
        return python_function(self.program())

    def torque_at(self, q: ArrayLike, qd: ArrayLike, qdd: ArrayLike) -> np.ndarray:
        """Torques of the simplified model at one state, in Python floats.

        Parameters
        ----------
        q, qd, qdd : array_like, shape (n,)
            Joint positions, velocities and accelerations [rad, rad/s, rad/s^2; m, m/s, m/s^2
            on a prismatic joint].

        Returns
        -------
        ndarray, shape (n,)
            tau_s [N m; N]: :meth:`torque` at that state, computed by the same program's
            operations in the same order on floats
            (:func:`~gd_analyze.symbolic.emit.state_function`), about ten times faster on
            one state (the closed loop's right-hand side); NaN everywhere when an input is not
            finite.

        Raises
        ------
        ValueError
            If an input does not have n entries.

        Examples
        --------
        >>> import numpy as np
        >>> from gd_analyze import load_robot
        >>> model = SimplifiedModel(load_robot("two-link"), full_choices(2), 0.5, 0.01)
        >>> s = (np.array([0.3, -0.2]), np.array([1.0, 0.5]), np.array([0.1, 2.0]))
        >>> bool(np.allclose(model.torque_at(*s), model.torque(*s)[0], rtol=1e-13))
        True
        """

        n = self.robot.n
        x = [np.asarray(v, dtype=float).reshape(-1) for v in (q, qd, qdd)]
        if any(v.size != n for v in x):
            raise ValueError(f"q, qd and qdd must have {n} entries each, got "
                             f"{[v.size for v in x]}")
        if not all(np.isfinite(v).all() for v in x):
            return np.full(n, np.nan)
        return np.array(state_function(self.program())(*(v.tolist() for v in x)))

    def torque(self, q: ArrayLike, qd: ArrayLike, qdd: ArrayLike) -> np.ndarray:
        """Torques of the simplified model, tau_s = D_s qdd + h_s + c, in explicit form.

        Parameters
        ----------
        q : array_like, shape (N, n) or (n,)
            Joint positions [rad].
        qd : array_like, shape (N, n) or (n,)
            Joint velocities [rad/s].
        qdd : array_like, shape (N, n) or (n,)
            Joint accelerations [rad/s^2].

        Returns
        -------
        ndarray, shape (N, n)
            Joint torques [N m].

        Raises
        ------
        ValueError
            If the arrays do not have n columns or disagree on N.
        """

        q, qd, qdd = as_states(self.robot, q, qd, qdd)
        return np.asarray(self._python_tau()(q, qd, qdd))   # evaluated in blocks

    def to_dict(self) -> dict:
        """The model in the layout of simplified_model.json.

        Returns
        -------
        dict
        """
        out = {
            "schema_version": SCHEMA_VERSION,
            "kind": "gd-analyze simplified model",
            "robot": {"name": self.robot.name, "sha256": self.robot.sha256,
                      "parameters_sha256": parameters_sha256(self.robot.to_dict()),
                      "source": self.robot.source, "parameters": self.robot.to_dict(),
                      **({"joint_names": self.robot.joint_names()}
                         if self.robot.metadata.get("urdf_joints") else {})},
            "mounting": self._mounting(),
            "dominance_threshold": self.dominance_threshold,
            "negligible_threshold": self.negligible_threshold,
            "choices": dict(self.choices),
            "rule": self.rule,
            "torque_floor": self.torque_floor,
            "trajectory_sha256": self.trajectory_sha256,
            "validation": self.validation,
            "provenance": self.provenance,
        }
        if self.terms is not None:
            out.update(cost=dict(self.cost or self.program().cost()), bound=list(self.bound),
                       explicit_terms=_terms_to_json(self.terms))
        out["form"] = self.form
        if self.recursive is not None:
            out.update(cost=dict(self.program().cost()),
                       bound=list(self.bound), recursive=self.recursive.to_dict())
        if self.costs:
            out["costs"] = {k: dict(v) for k, v in self.costs.items()}
        if np.isfinite(self.tolerance):
            out["tolerance"] = self.tolerance
        if self.full_cost:
            out["full_cost"] = dict(self.full_cost)
        if self.guarantee is not None:
            out["guarantee"] = self.guarantee.to_dict()
        if self.inertia_check is not None:
            out["inertia_check"] = dict(self.inertia_check)
        return out

    def _mounting(self):
        """The mounting the model was built with, for the file (``mounting``)."""

        rpy, g_world = mounting_of(self.robot)
        return {"base_rpy_deg": [float(v) for v in rpy],
                "gravity_world": [float(v) for v in g_world]}

    def scope(self) -> str:
        """Where the model's bound holds, in one sentence.

        Returns
        -------
        str
            :meth:`~gd_analyze.simplify.guarantee.Guarantee.statement`, or for a model
            without a guarantee (chapter rule) that it has none.
        """
        if self.guarantee is not None:
            return self.guarantee.statement()
        return "no bound: share-based classes of the chapter (Sec. 3.4.1)" if self.rule == \
            "chapter" else "no bound stated (a model of the budget rule built without one)"

    @classmethod
    def from_dict(cls, spec: dict, robot: Robot, path: str = "<dict>") -> SimplifiedModel:
        """The model from a parsed simplified_model.json (see :func:`gd_analyze.store.model_file.load_model`).

        Parameters
        ----------
        spec : dict
            The document, already checked against
            :data:`gd_analyze.store.json_schema.MODEL_SCHEMA`.
        robot : Robot
            Its robot, rebuilt from ``spec["robot"]["parameters"]``.
        path : str
            The file, for error messages.

        Returns
        -------
        SimplifiedModel

        Raises
        ------
        InputError
            If the robot's name differs from ``robot.name``, the choices do not name exactly
            the elements of an n-joint robot, the explicit or recursive terms are invalid, or
            the program rebuilt from the stored pairs or terms is not the file's (a dropped
            pair it keeps, another ``cost``). One line naming the key.

        Notes
        -----
        The document's ``cost`` and ``full_cost`` are not read as counts: a claim is not a
        count. The model's cost is counted from its terms (:meth:`program`) wherever it is
        shown or written; the stored ``cost`` is only compared with it.
        """
        rob = spec["robot"]
        if robot.name != rob["name"]:
            raise InputError(f"robot.name {rob['name']!r} differs from the parameters' name "
                             f"{robot.name!r}", path, column="robot.name")
        labels = element_labels(robot.n)
        choices = spec["choices"]
        if set(choices) != set(labels):
            extra = sorted(set(choices) - set(labels))
            missing = [lab for lab in labels if lab not in choices]
            raise InputError((f"unknown element {extra[0]!r}" if extra else
                              f"missing element {missing[0]!r}")
                             + f" (a {robot.n}-joint robot has {labels[0]}..{labels[-1]})",
                             path, column="choices")
        if "pruned" in choices.values() and spec.get("form") != "recursive":
            raise InputError("choice 'pruned' belongs to a model of the recursive form", path,
                             column="choices")
        try:
            terms = _terms_from_json(spec.get("explicit_terms"), robot.n, robot.prismatic)
        except (ValueError, TypeError) as exc:
            raise InputError(f"invalid explicit terms: {exc}"[:200], path,
                             column="explicit_terms") from None
        recursive = None
        if spec.get("form") == "recursive" or "recursive" in spec:
            if "recursive" not in spec or spec.get("form") != "recursive":
                raise InputError("a model of the recursive form needs both 'form' and "
                                 "'recursive'", path, column="form")
            recursive = RecursiveModel.from_dict(spec["recursive"], robot, path)
            terms = None
        tolerance = float(spec.get("tolerance", "nan"))       # NaN: no budget (schema 1)
        guarantee = None
        if spec.get("guarantee") is not None:
            guarantee = Guarantee.from_dict(spec["guarantee"], robot.n, tolerance, path)
            if guarantee.region is not None and not np.array_equal(
                    guarantee.region.is_prismatic, np.asarray(robot.prismatic, bool)):
                raise InputError("its joint types are not the robot's",
                                 path, column="guarantee.region.prismatic")
        model = cls(robot=robot, choices=dict(choices),
                   dominance_threshold=float(spec["dominance_threshold"]),
                   negligible_threshold=float(spec["negligible_threshold"]),
                   trajectory_sha256=spec.get("trajectory_sha256", ""),
                   validation=spec.get("validation", {}),
                   provenance=spec.get("provenance", {}),
                   rule=spec.get("rule", "chapter"),
                   tolerance=tolerance,
                   torque_floor=float(spec.get("torque_floor", 0.0)), terms=terms,
                   cost={}, full_cost={},
                   bound=[float("nan") if v is None else float(v)
                          for v in spec.get("bound") or []],
                   recursive=recursive, costs=dict(spec.get("costs") or {}),
                   guarantee=guarantee)

        check_program(model, spec.get("cost"), path)
        return model


def parameters_sha256(parameters: dict) -> str:
    """SHA-256 of a robot's parameters as stored in a model file (canonical JSON).

    Parameters
    ----------
    parameters : dict
        :meth:`~gd_analyze.model.robot.Robot.to_dict` output, or the same as read back from
        JSON.

    Returns
    -------
    str
        64 hexadecimal digits of the SHA-256 of ``json.dumps(parameters, sort_keys=True)``;
        a float survives the JSON round trip exactly, so the digest does too.
    """
    import hashlib

    text = json.dumps(json_safe(parameters), sort_keys=True, allow_nan=False)
    return hashlib.sha256(text.encode()).hexdigest()


def _terms_to_json(terms):
    return {"kind": [str(v) for v in terms.kind], "part": [str(v) for v in terms.part],
            "i": terms.i.tolist(), "j": terms.j.tolist(), "k": terms.k.tolist(),
            "K": terms.K.tolist(), "sin": terms.S.tolist(), "coef": terms.C.tolist()}


def _terms_from_json(spec, n, prismatic=None):
    """The kept terms from JSON, or None (older layouts); K in the canonical form of
    :mod:`gd_analyze.symbolic.trigpoly` (no negative power of a prismatic joint's q, each row's
    first non-zero harmonic positive), the only one the code generator forms."""
    if spec is None:
        return None

    size = len(spec["coef"])
    K = np.array(spec["K"], dtype=np.int64).reshape(size, n)
    out = Term(np.array(spec["kind"], dtype=str), np.array(spec["part"], dtype=str),
               np.array(spec["i"], int), np.array(spec["j"], int), np.array(spec["k"], int),
               K, np.array(spec["sin"], bool), np.array(spec["coef"], float))
    for f in ("kind", "part", "i", "j", "k", "S", "C"):
        if getattr(out, f).shape != (size,):
            raise ValueError(f"explicit_terms.{f}: expected {size} values")
    if not all(isinstance(v, bool) for v in spec["sin"]):
        raise ValueError("explicit_terms.sin: expected true/false")
    if not np.isfinite(out.C).all():
        raise ValueError("explicit_terms.coef: not finite")
    if size and (out.i.min() < 0 or out.i.max() >= n or out.j.max() >= n or out.k.max() >= n):
        raise ValueError("explicit_terms: joint index out of range")
    lin = np.zeros(n, bool) if prismatic is None else np.asarray(prismatic, bool)
    harmonics = K[:, ~lin]
    first = harmonics[np.arange(size), np.argmax(harmonics != 0, axis=1)] if harmonics.size \
        else K[:0, 0]
    if (K[:, lin] < 0).any() or (first < 0).any():
        raise ValueError("explicit_terms.K: not in canonical form (a negative power, or a row "
                         "whose first non-zero harmonic is negative)")
    bad = set(out.kind.tolist()) - {"D", "h", "c"}
    if bad:
        raise ValueError(f"explicit_terms.kind: unknown {sorted(bad)[0]!r}")
    return out


def json_safe(obj: object) -> object:
    """Replace NaN/inf (not valid JSON) by None, recursively; numpy scalars by Python ones.

    Parameters
    ----------
    obj : object
        Nested dicts, lists, tuples, floats and numpy scalars.

    Returns
    -------
    object
        The same structure, ready for strict JSON (RFC 8259 has no NaN).

    Examples
    --------
    >>> json_safe({"a": [1.0, float("nan")], "b": np.float64(2.0)})
    {'a': [1.0, None], 'b': 2.0}
    """
    if isinstance(obj, dict):
        return {k: json_safe(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [json_safe(v) for v in obj]
    if isinstance(obj, float) and not np.isfinite(obj):
        return None
    if isinstance(obj, np.generic):
        return json_safe(obj.item())
    return obj


def total_operations(cost: Mapping[str, Any]) -> int:
    """Multiplications plus additions of a counted cost (Table 3.5's measure).

    Parameters
    ----------
    cost : mapping
        With ``multiplications`` and ``additions``.

    Returns
    -------
    int

    Examples
    --------
    >>> total_operations({"multiplications": 169, "additions": 143})
    312
    """
    return int(cost["multiplications"]) + int(cost["additions"])
