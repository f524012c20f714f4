"""The names in ``results.h5``: every variable and global attribute as a constant.

One module of names, so that the writers (:mod:`gd_analyze.store.datasets`,
:mod:`gd_analyze.store.schema`) and the readers (:mod:`gd_analyze.store.results_view`, the report and
the command line) spell them once: a typo is an ``AttributeError`` at import or a linter's
warning, not a report that fails to render. The file's contents are those of
:mod:`gd_analyze.store.datasets`; this module only names them.

Examples
--------
>>> Var.SHARE_TRAN, Attr.DOMINANCE_THRESHOLD
('share_tran', 'dominance_threshold')
>>> Var.SHARE_TRAN in VARIABLES
True
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Final

__all__ = ["Var", "Attr", "ControlVar", "SweepVar", "SweepAttr", "VARIABLES", "ATTRIBUTES", "CONTROL_VARIABLES", "SWEEP_VARIABLES", "SWEEP_ATTRIBUTES", "VERIFICATION_PREFIX",
           "VERIFIED_TERMS", "verification_attribute", "ELEMENT_UNITS_RULE", "CliShown",
           "ReportShown", "RankingColumn", "RANKING_COLUMNS"]


class _Shared:
    """The variables and coordinates ``results.h5``, ``control.h5`` and ``sweep.h5`` name
    alike: the element and joint dims, the joints' types, the part kept per element and each
    joint's peak |tau|. A base of :class:`Var`, :class:`ControlVar` and :class:`SweepVar`."""

    __slots__ = ()

    ELEMENT: Final = "element"
    JOINT: Final = "joint"
    JOINT_TYPE: Final = "joint_type"
    CHOICE: Final = "choice"
    TAU_PEAK: Final = "tau_peak"


class _Ranked(_Shared):
    """The ranking's variables that ``results.h5`` and ``sweep.h5`` name alike (per element,
    and per joint the simplified model's torque error). A base of :class:`Var` and
    :class:`SweepVar`."""

    __slots__ = ()

    SHARE_TRAN: Final = "share_tran"
    DOMINANCE: Final = "dominance"
    PEAK_TOTAL: Final = "peak_total"
    ROUND_OFF: Final = "round_off"   # of a sweep, a payload sweep (results.h5: payload_round_off)
    TAU_ERROR_PEAK: Final = "tau_error_peak"
    TAU_ERROR_RMS: Final = "tau_error_rms"
    TAU_ERROR_RELATIVE_PEAK: Final = "tau_error_relative_peak"
    TAU_ERROR_RELATIVE_RMS: Final = "tau_error_relative_rms"
    BASE_PARAMETER: Final = "base_parameter"


class _Provenance:
    """The global attributes of ``results.h5`` and ``sweep.h5`` alike: those of every
    gd-analyze dataset (:func:`gd_analyze.store.schema.global_attributes`), the ranking's
    thresholds, the command, the payload's mass and the mounting. A base of :class:`Attr`
    and :class:`SweepAttr`."""

    __slots__ = ()

    CONVENTIONS: Final = "Conventions"
    TITLE: Final = "title"
    SOURCE: Final = "source"
    REFERENCES: Final = "references"
    HISTORY: Final = "history"
    GD_ANALYZE_VERSION: Final = "gd_analyze_version"
    ROBOT: Final = "robot"
    ROBOT_DESCRIPTION: Final = "robot_description"
    ROBOT_REFERENCE: Final = "robot_reference"
    ROBOT_SOURCE: Final = "robot_source"
    ROBOT_SHA256: Final = "robot_sha256"
    GRAVITY: Final = "gravity"
    GRAVITY_UNITS: Final = "gravity_units"
    DOMINANCE_THRESHOLD: Final = "dominance_threshold"
    NEGLIGIBLE_THRESHOLD: Final = "negligible_threshold"
    COMMAND: Final = "command"
    PAYLOAD_MASS: Final = "payload_mass"
    MOUNTING_BASE_RPY_DEG: Final = "mounting_base_rpy_deg"
    MOUNTING_GRAVITY_BASE: Final = "mounting_gravity_base"
    MOUNTING_GRAVITY_WORLD: Final = "mounting_gravity_world"


class Var(_Ranked):
    """Variables and coordinates of ``results.h5`` (:mod:`gd_analyze.store.datasets`).

    Each constant is the variable's name; ``Var.D_TRAN == "D_tran"``. Not instantiated.
    """

    __slots__ = ()

    D: Final = "D"
    D_ARM: Final = "D_arm"
    D_ROT: Final = "D_rot"
    D_TRAN: Final = "D_tran"
    BASE_PARAMETER_DROPPED: Final = "base_parameter_dropped"
    BASE_PARAMETER_RELATIVE_PEAK: Final = "base_parameter_relative_peak"
    BASE_PARAMETER_UNITS: Final = "base_parameter_units"
    BASE_PARAMETER_VALUE: Final = "base_parameter_value"
    C: Final = "c"
    CHAPTER_AGREEMENT: Final = "chapter_agreement"
    CHAPTER_DOMINANCE: Final = "chapter_dominance"
    CHAPTER_MODEL_CHOICE: Final = "chapter_model_choice"
    CHAPTER_MODEL_ERROR_RELATIVE_PEAK: Final = "chapter_model_error_relative_peak"
    CHAPTER_MODEL_ERROR_ROUND_OFF: Final = "chapter_model_error_round_off"
    CHAPTER_THRESHOLD: Final = "chapter_threshold"
    COST_ADDITIONS: Final = "cost_additions"
    COST_MODEL: Final = "cost_model"
    COST_MULTIPLICATIONS: Final = "cost_multiplications"
    COST_TOTAL: Final = "cost_total"
    COULOMB: Final = "coulomb"
    DH_A: Final = "dh_a"
    DH_ALPHA: Final = "dh_alpha"
    DH_D: Final = "dh_d"
    DH_OFFSET: Final = "dh_offset"
    DOF: Final = "dof"
    DOMINANCE_RIGID_LINKS: Final = "dominance_rigid_links"
    ELEMENT_ROUND_OFF: Final = "element_round_off"
    ELEMENT_SCALE: Final = "element_scale"
    ELEMENT_UNITS: Final = "element_units"
    FORMULATION: Final = "formulation"
    FORMULATION_DISAGREEMENT: Final = "formulation_disagreement"
    FORMULATION_PAIR: Final = "formulation_pair"
    H: Final = "h"
    H_ROT: Final = "h_rot"
    H_TRAN: Final = "h_tran"
    JOINT_K: Final = "joint_k"
    JOINT_ROTATION: Final = "joint_rotation"
    JOINT_TRANSLATION: Final = "joint_translation"
    LADDER_OPERATIONS: Final = "ladder_operations"
    LADDER_TOLERANCE: Final = "ladder_tolerance"
    LADDER_TRIG: Final = "ladder_trig"
    LADDER_WORST_BOUND: Final = "ladder_worst_bound"
    LADDER_WORST_ERROR: Final = "ladder_worst_error"
    LINK_COM: Final = "link_com"
    LINK_INERTIA: Final = "link_inertia"
    LINK_MASS: Final = "link_mass"
    OP_ADDITIONS: Final = "op_additions"
    OP_ADDITIONS_ARM: Final = "op_additions_arm"
    OP_ADDITIONS_TABLE_3_5: Final = "op_additions_table_3_5"
    OP_MULTIPLICATIONS: Final = "op_multiplications"
    OP_MULTIPLICATIONS_ARM: Final = "op_multiplications_arm"
    OP_MULTIPLICATIONS_TABLE_3_5: Final = "op_multiplications_table_3_5"
    OTHER_RULE_CHOICE: Final = "other_rule_choice"
    OTHER_RULE_ERROR_RELATIVE_PEAK: Final = "other_rule_error_relative_peak"
    PAYLOAD: Final = "payload"
    PAYLOAD_CHOICE: Final = "payload_choice"
    PAYLOAD_DOMINANCE: Final = "payload_dominance"
    PAYLOAD_PEAK_TOTAL: Final = "payload_peak_total"
    PAYLOAD_ROUND_OFF: Final = "payload_round_off"
    PAYLOAD_SHARE_TRAN: Final = "payload_share_tran"
    PAYLOAD_TAU_ERROR_RELATIVE_PEAK: Final = "payload_tau_error_relative_peak"
    PAYLOAD_TAU_PEAK: Final = "payload_tau_peak"
    PEAK_ROT: Final = "peak_rot"
    PEAK_ROT_ROUND_OFF: Final = "peak_rot_round_off"
    PEAK_TOTAL_ROUND_OFF: Final = "peak_total_round_off"
    PEAK_TRAN: Final = "peak_tran"
    PEAK_TRAN_ROUND_OFF: Final = "peak_tran_round_off"
    Q: Final = "q"
    Q_MAX: Final = "q_max"
    Q_MIN: Final = "q_min"
    Q_UNITS: Final = "q_units"
    QD: Final = "qd"
    QD_MAX: Final = "qd_max"
    QD_UNITS: Final = "qd_units"
    QDD: Final = "qdd"
    QDD_MAX: Final = "qdd_max"
    QDD_UNITS: Final = "qdd_units"
    QUANTITY: Final = "quantity"
    REGION_Q_FULL_TURN: Final = "region_q_full_turn"
    REGION_Q_MAX: Final = "region_q_max"
    REGION_Q_MIN: Final = "region_q_min"
    REGION_QD_MAX: Final = "region_qd_max"
    REGION_QDD_MAX: Final = "region_qdd_max"
    REGION_QDD_MAX_ASSUMED: Final = "region_qdd_max_assumed"
    SHARE_ARM: Final = "share_arm"
    SIMPLIFIED_BOUND: Final = "simplified_bound"
    SIMPLIFIED_BOUND_CORIOLIS: Final = "simplified_bound_coriolis"
    SIMPLIFIED_BOUND_GRAVITY: Final = "simplified_bound_gravity"
    SIMPLIFIED_BOUND_INERTIA: Final = "simplified_bound_inertia"
    SIMPLIFIED_BOUND_WHOLE: Final = "simplified_bound_whole"
    SIMPLIFIED_ELEMENT_BOUND: Final = "simplified_element_bound"
    SIMPLIFIED_GUARANTEE_BOUND: Final = "simplified_guarantee_bound"
    SIMPLIFIED_GUARANTEE_BOUND_METHOD: Final = "simplified_guarantee_bound_method"
    SIMPLIFIED_GUARANTEE_SCALE: Final = "simplified_guarantee_scale"
    SIMPLIFIED_SCALE: Final = "simplified_scale"
    T: Final = "t"
    TAU: Final = "tau"
    TAU_ERROR_ROUND_OFF: Final = "tau_error_round_off"
    TAU_F: Final = "tau_f"
    TAU_MAX: Final = "tau_max"
    TAU_SIMPLIFIED: Final = "tau_simplified"
    TAU_UNITS: Final = "tau_units"
    TORQUE_OFFSET: Final = "torque_offset"
    TORQUE_PART: Final = "torque_part"
    VISCOUS: Final = "viscous"
    XYZ: Final = "xyz"
    XYZ_K: Final = "xyz_k"


class Attr(_Provenance):
    """Global attributes of ``results.h5``: provenance, thresholds, settings, the verification
    against Pinocchio and the simplified model's summary (:func:`gd_analyze.store.schema.global_attributes`,
    :func:`gd_analyze.store.datasets.summary_dataset`).

    Each constant is the attribute's name; ``Attr.SETPOINTS == "setpoints"``. Not
    instantiated.
    """

    __slots__ = ()

    CHAPTER_ARM_RANKED: Final = "chapter_arm_ranked"
    CHAPTER_ARM_TRANSLATION_LEADS: Final = "chapter_arm_translation_leads"
    CHAPTER_ELEMENTS_COMPARED: Final = "chapter_elements_compared"
    CHAPTER_WRIST_RANKED: Final = "chapter_wrist_ranked"
    CHAPTER_WRIST_ROTATION_LEADS: Final = "chapter_wrist_rotation_leads"
    C_PREFIX: Final = "c_prefix"
    DERIVATIVES: Final = "derivatives"
    EXPLICIT: Final = "explicit"
    FORM: Final = "form"
    FORMULATIONS_JOINT_TYPES: Final = "formulations_joint_types"
    FORMULATIONS_N: Final = "formulations_n"
    FORMULATIONS_SETPOINTS: Final = "formulations_setpoints"
    FULL_COEFFICIENTS: Final = "full_coefficients"
    FULL_HARMONICS: Final = "full_harmonics"
    GUARANTEE: Final = "guarantee"
    INPUT_FILE: Final = "input_file"
    INPUT_PATH: Final = "input_path"
    INPUT_SHA256: Final = "input_sha256"
    OTHER_RULE: Final = "other_rule"
    OTHER_RULE_ADDITIONS: Final = "other_rule_additions"
    OTHER_RULE_COEFFICIENTS: Final = "other_rule_coefficients"
    OTHER_RULE_HARMONICS: Final = "other_rule_harmonics"
    OTHER_RULE_MULTIPLICATIONS: Final = "other_rule_multiplications"
    PAYLOAD_COM: Final = "payload_com"
    PAYLOAD_INERTIA: Final = "payload_inertia"
    REGION_COVERAGE: Final = "region_coverage"
    REGION_COVERS_TRAJECTORY: Final = "region_covers_trajectory"
    REGION_NOTES: Final = "region_notes"
    REGION_SOURCE: Final = "region_source"
    REGION_SUMMARY: Final = "region_summary"
    ROBOT_BASE: Final = "robot_base"
    ROBOT_PLACEHOLDER_INERTIA: Final = "robot_placeholder_inertia"
    ROBOT_TIP: Final = "robot_tip"
    RULE: Final = "rule"
    SETPOINTS: Final = "setpoints"
    SIMPLIFIED_ADDITIONS: Final = "simplified_additions"
    SIMPLIFIED_COS: Final = "simplified_cos"
    SIMPLIFIED_DROPPED_PAIRS: Final = "simplified_dropped_pairs"
    SIMPLIFIED_FILES: Final = "simplified_files"
    SIMPLIFIED_FORM: Final = "simplified_form"
    SIMPLIFIED_FORM_NOTE: Final = "simplified_form_note"
    SIMPLIFIED_GUARANTEE_JOINT_SUM_ARITHMETIC: Final = \
        "simplified_guarantee_joint_sum_arithmetic"
    SIMPLIFIED_GUARANTEE_KIND: Final = "simplified_guarantee_kind"
    SIMPLIFIED_GUARANTEE_SCALE_SOURCE: Final = "simplified_guarantee_scale_source"
    SIMPLIFIED_GUARANTEE_STATEMENT: Final = "simplified_guarantee_statement"
    SIMPLIFIED_GUARANTEE_TOLERANCE: Final = "simplified_guarantee_tolerance"
    SIMPLIFIED_INERTIA_CHECK_LOWER_BOUND: Final = "simplified_inertia_check_lower_bound"
    SIMPLIFIED_INERTIA_CHECK_METHOD: Final = "simplified_inertia_check_method"
    SIMPLIFIED_INERTIA_CHECK_PROVED: Final = "simplified_inertia_check_proved"
    SIMPLIFIED_INERTIA_CHECK_RATIO: Final = "simplified_inertia_check_ratio"
    SIMPLIFIED_INERTIA_CHECK_RESTORED: Final = "simplified_inertia_check_restored"
    SIMPLIFIED_INERTIA_CHECK_SAMPLED_MIN_EIGENVALUE: Final = "simplified_inertia_check_sampled_min_eigenvalue"
    SIMPLIFIED_INERTIA_CHECK_SAMPLES: Final = "simplified_inertia_check_samples"
    SIMPLIFIED_INERTIA_CHECK_STATEMENT: Final = "simplified_inertia_check_statement"
    SIMPLIFIED_INERTIA_CHECK_WHERE: Final = "simplified_inertia_check_where"
    SIMPLIFIED_LADDER_FORM: Final = "simplified_ladder_form"
    SIMPLIFIED_LADDER_SKIPPED: Final = "simplified_ladder_skipped"
    SIMPLIFIED_MULTIPLICATIONS: Final = "simplified_multiplications"
    SIMPLIFIED_PAIRS: Final = "simplified_pairs"
    SIMPLIFIED_REGION_POSSIBLE_SAVING: Final = "simplified_region_possible_saving"
    SIMPLIFIED_REGION_SAVING_THRESHOLD: Final = "simplified_region_saving_threshold"
    SIMPLIFIED_REGION_SCREEN: Final = "simplified_region_screen"
    SIMPLIFIED_REGION_SCREEN_PROVED: Final = "simplified_region_screen_proved"
    SIMPLIFIED_PAIRS_DROPPED: Final = "simplified_pairs_dropped"
    SIMPLIFIED_RULE: Final = "simplified_rule"
    SIMPLIFIED_SIN: Final = "simplified_sin"
    SIMPLIFIED_TERMS_KEPT: Final = "simplified_terms_kept"
    SIMPLIFIED_TOLERANCE: Final = "simplified_tolerance"
    SIMPLIFIED_TORQUE_FLOOR: Final = "simplified_torque_floor"
    TOLERANCE: Final = "tolerance"
    TORQUE_FLOOR: Final = "torque_floor"
    VERIFICATION_ENGINE: Final = "verification_engine"
    VERIFICATION_PASSED: Final = "verification_passed"
    VERIFICATION_SETPOINTS: Final = "verification_setpoints"
    VERIFICATION_TOLERANCE: Final = "verification_tolerance"


class ControlVar(_Shared):
    """Variables and coordinates of ``control.h5``
    (:func:`gd_analyze.store.control_dataset.control_dataset`; read by
    :class:`gd_analyze.store.stored_control.StoredControl`).

    Each constant is the variable's name; ``ControlVar.KP_PD == "Kp_pd"``. The units of a
    gain whose units depend on the joint's type are the coordinate ``<gain>_units``; the
    joints' units and the region are :class:`Var`'s, as in ``results.h5``. Not
    instantiated.
    """

    __slots__ = ()

    IS_SETPOINT: Final = "is_setpoint"
    Q_D: Final = "q_d"
    QD_D: Final = "qd_d"
    QDD_D: Final = "qdd_d"
    Q: Final = "q"
    QD: Final = "qd"
    TAU: Final = "tau"
    ERROR: Final = "error"
    ERROR_PEAK_SETPOINTS: Final = "error_peak_setpoints"
    ERROR_RMS_SETPOINTS: Final = "error_rms_setpoints"
    ERROR_PEAK_GRID: Final = "error_peak_grid"
    ERROR_RMS_GRID: Final = "error_rms_grid"
    TAU_RMS: Final = "tau_rms"
    NFEV: Final = "nfev"
    SUCCESS: Final = "success"
    WN: Final = "wn"
    ZETA: Final = "zeta"
    KP: Final = "Kp"
    KV: Final = "Kv"
    INERTIA_SCALE: Final = "inertia_scale"
    KP_PD: Final = "Kp_pd"
    KV_PD: Final = "Kv_pd"
    INERTIA_SCALE_UNITS: Final = "inertia_scale_units"
    KP_PD_UNITS: Final = "Kp_pd_units"
    KV_PD_UNITS: Final = "Kv_pd_units"
    Q0_OFFSET: Final = "q0_offset"
    TAU_DIFFERENCE: Final = "tau_difference"
    TAU_DIFFERENCE_PEAK: Final = "tau_difference_peak"
    TAU_DIFFERENCE_RMS: Final = "tau_difference_rms"
    TAU_DIFFERENCE_PEAK_SETPOINTS: Final = "tau_difference_peak_setpoints"
    TAU_DIFFERENCE_RMS_SETPOINTS: Final = "tau_difference_rms_setpoints"
    TAU_DIFFERENCE_NOISE: Final = "tau_difference_noise"
    TAU_DIFFERENCE_FLOOR: Final = "tau_difference_floor"
    CONTROLLER: Final = "controller"
    CONTROLLER_DESCRIPTION: Final = "controller_description"
    TIME: Final = "time"
    EVALUATOR: Final = "evaluator"
    MULTIPLICATIONS: Final = "multiplications"
    ADDITIONS: Final = "additions"


class SweepVar(_Ranked):
    """Variables and coordinates of ``sweep.h5``
    (:func:`gd_analyze.store.sweep_view.sweep_dataset`, the merged model's by
    :mod:`gd_analyze.jobs.sweep_merged`; read by :class:`gd_analyze.store.sweep_view.StoredSweep`).

    Each constant is the variable's name; ``SweepVar.SHARE_TRAN_MIN == "share_tran_min"``. Not
    instantiated.
    """

    __slots__ = ()

    SOURCE: Final = "source"
    INPUT_SHA256: Final = "input_sha256"
    DURATION: Final = "duration"
    SETPOINTS: Final = "setpoints"
    Q_START: Final = "q_start"
    Q_GOAL: Final = "q_goal"
    MERGED_TAU_ERROR_PEAK: Final = "merged_tau_error_peak"
    MERGED_TAU_ERROR_RELATIVE_PEAK: Final = "merged_tau_error_relative_peak"
    CLASS_FRACTION: Final = "class_fraction"
    SHARE_TRAN_MIN: Final = "share_tran_min"
    SHARE_TRAN_MEDIAN: Final = "share_tran_median"
    SHARE_TRAN_MAX: Final = "share_tran_max"
    MERGED_CHOICE: Final = "merged_choice"
    MERGED_ERROR_PEAK: Final = "merged_error_peak"
    MERGED_ERROR_RMS: Final = "merged_error_rms"
    MERGED_ERROR_TAU_PEAK: Final = "merged_error_tau_peak"
    MERGED_ERROR_RELATIVE_PEAK: Final = "merged_error_relative_peak"
    MERGED_ERROR_RELATIVE_RMS: Final = "merged_error_relative_rms"
    TRAJECTORY: Final = "trajectory"
    CLASS: Final = "class"
    MERGED_SCALE: Final = "merged_scale"
    MERGED_BOUND: Final = "merged_bound"
    MERGED_BOUND_METHOD: Final = "merged_bound_method"
    MERGED_COVERED: Final = "merged_covered"
    MERGED_COVERAGE: Final = "merged_coverage"
    HELD_OUT_ERROR_PEAK: Final = "held_out_error_peak"
    HELD_OUT_TAU_PEAK: Final = "held_out_tau_peak"
    PAIR_TAU_PEAK: Final = "pair_tau_peak"
    PAIR_PEAK: Final = "pair_peak"
    PARAMETER_PEAK: Final = "parameter_peak"
    PART: Final = "part"
    EVALUATOR: Final = "evaluator"
    MULTIPLICATIONS: Final = "multiplications"
    ADDITIONS: Final = "additions"


class SweepAttr(_Provenance):
    """Global attributes of ``sweep.h5`` that the sweep report says in rows of their own, or
    that are results; any other attribute is a setting (:class:`gd_analyze.store.sweep_view.SweepSettings`).

    Each constant is the attribute's name; ``SweepAttr.MERGED_RULE == "merged_rule"``. Not
    instantiated.
    """

    __slots__ = ()

    SEED: Final = "seed"
    INPUT_FILES: Final = "input_files"
    INPUTS_SHA256: Final = "inputs_sha256"
    SETPOINTS_TOTAL: Final = "setpoints_total"
    MERGE_RULE: Final = "merge_rule"
    CLUSTER: Final = "cluster"
    N_WORKERS: Final = "n_workers"
    SCHEDULER_ADDRESS: Final = "scheduler_address"
    N_TASKS: Final = "n_tasks"
    BATCH_SIZE: Final = "batch_size"
    ELAPSED_S: Final = "elapsed_s"
    COMPUTE_S: Final = "compute_s"
    INPUT_KIND: Final = "input_kind"
    TRAJECTORIES: Final = "trajectories"
    STARTED: Final = "started"
    MERGED_RULE: Final = "merged_rule"
    MERGED_TOLERANCE: Final = "merged_tolerance"
    MERGED_TORQUE_FLOOR: Final = "merged_torque_floor"
    MERGED_WORST_SCALED_ERROR: Final = "merged_worst_scaled_error"
    RANDOM_QDD_MAX_SOURCE: Final = "random_qdd_max_source"
    OWN_MODEL_RULE: Final = "own_model_rule"
    MERGED_FORM: Final = "merged_form"
    MERGED_C_TERMS: Final = "merged_c_terms"
    MERGED_C_TERMS_KEPT: Final = "merged_c_terms_kept"
    HELD_OUT_TRAJECTORIES: Final = "held_out_trajectories"
    MERGED_BASE_PARAMETERS: Final = "merged_base_parameters"
    MERGED_PAIRS: Final = "merged_pairs"
    MERGED_PAIRS_DROPPED: Final = "merged_pairs_dropped"
    MERGED_DROPPED_PAIRS: Final = "merged_dropped_pairs"
    MERGED_GRAVITY_DROPPED: Final = "merged_gravity_dropped"
    MERGED_GUARANTEE_KIND: Final = "merged_guarantee_kind"
    MERGED_JOINT_SUM_ARITHMETIC: Final = "merged_joint_sum_arithmetic"
    MERGED_GUARANTEE_STATEMENT: Final = "merged_guarantee_statement"
    MERGED_GUARANTEE_SCALE_SOURCE: Final = "merged_guarantee_scale_source"
    HELD_OUT_INSIDE_REGION: Final = "held_out_inside_region"


def _values(namespace: type) -> frozenset:
    return frozenset(v for c in namespace.__mro__ for k, v in vars(c).items() if k.isupper())


#: Every variable name of :class:`Var`.
VARIABLES: Final = _values(Var)
#: Every variable name of :class:`ControlVar`.
CONTROL_VARIABLES: Final = _values(ControlVar)
#: Every variable name of :class:`SweepVar`.
SWEEP_VARIABLES: Final = _values(SweepVar)
#: Every attribute name of :class:`SweepAttr`.
SWEEP_ATTRIBUTES: Final = _values(SweepAttr)
#: The prefix of the attributes of the check against Pinocchio.
VERIFICATION_PREFIX: Final = "verification_"
#: The terms checked against Pinocchio, each with a largest relative error and excess.
VERIFIED_TERMS: Final = ("D", "D_tran", "D_rot", "h", "h_tran", "h_rot", "c")


def verification_attribute(term: str, excess: bool = False) -> str:
    """The attribute of a term's largest relative disagreement with Pinocchio.

    Parameters
    ----------
    term : str
        One of :data:`VERIFIED_TERMS`.
    excess : bool, optional
        The disagreement beyond round-off (64 eps of its scale) rather than the whole.

    Returns
    -------
    str
        ``"verification_max_rel_error_<term>"`` or ``"verification_max_rel_excess_<term>"``,
        the one spelling of these attributes (each is in :data:`ATTRIBUTES`).

    Examples
    --------
    >>> verification_attribute("D_tran")
    'verification_max_rel_error_D_tran'
    >>> verification_attribute("c", excess=True)
    'verification_max_rel_excess_c'
    """
    return f"{VERIFICATION_PREFIX}max_rel_{'excess' if excess else 'error'}_{term}"


#: Every attribute name of :class:`Attr`, and those of :func:`verification_attribute`.
ATTRIBUTES: Final = _values(Attr) | {verification_attribute(term, excess)
                                     for term in VERIFIED_TERMS for excess in (False, True)}


#: The units rule of a ranking column whose values are in its element's own units
#: (``element_units``: kg m2, kg m or kg for D; N m or N for h).
ELEMENT_UNITS_RULE: Final = "element"


@dataclass(frozen=True)
class CliShown:
    """How the command line's ranking table shows a column.

    Attributes
    ----------
    header : str
        The column's heading.
    align : str
        The format spec's alignment and width of heading and cells (``">11"``, ``"<14"``;
        ``""``: as wide as the text, the last column).
    number : str
        The format spec of a number (``".4f"``, ``".4g"``); ``""`` for text. A number of an
        element zero in every part is shown as "\u2261 0".
    lead : str
        What goes before the column (the gap after the previous one).
    """

    header: str
    align: str
    number: str = ""
    lead: str = ""


@dataclass(frozen=True)
class ReportShown:
    """How the report's ranking table (Sec. 4) shows a column.

    Attributes
    ----------
    header : str
        The heading; ``{X}`` in it stands for the element's symbol, with ``part`` as its
        superscript.
    kind : str
        How the cells are written:

        - ``"label"``: the element (lettered as the figures letter it);
        - ``"share"``: the translational share, "\u2261 0" for an element zero in every
          part, 0 or 1 where the other part's peak is round-off;
        - ``"armature_share"``: the armature share on D's diagonal, "\u2014" elsewhere;
          shown only for an arm with drives;
        - ``"class"``: a dominance class, drawn in its colour;
        - ``"peak"``: a peak of one of the element's parts [element's units], in one number
          format with the other peaks, "\u2261 0" where its round-off flag is set;
        - ``"armature_peak"``: the armature on D's diagonal, in the peaks' format, "\u2014"
          elsewhere; shown only for an arm with drives;
        - ``"number"``: a number in a format of its own column, "\u2261 0" for an element
          zero in every part;
        - ``"units"``: the element's units, as the text writes them.
    width : float
        Relative width in the PDF.
    part : str or None
        The superscript of ``{X}``: ``"tran"``, ``"rot"``, ``"arm"``, or None.
    """

    header: str
    kind: str
    width: float
    part: str | None = None


@dataclass(frozen=True)
class RankingColumn:
    """One per-element column of the dominance ranking: where it comes from, how it is stored
    and how each renderer shows it.

    Attributes
    ----------
    name : str
        Its variable in ``results.h5`` (a constant of :class:`Var`), or its name in the
        results view where ``stored`` is False.
    field : str
        Its field in :class:`gd_analyze.store.results_view.RankingTable`, and, for
        ``source="ranking"``, the attribute of
        :class:`gd_analyze.ranking.ranking.Ranking` it is written from.
    source : str
        ``"ranking"`` (the Ranking's attribute), ``"choices"`` (the simplified model's choice
        per element), ``"chapter"`` (the class Sec. 3.4.1 reports for the PUMA 560),
        ``"coordinate"`` (a coordinate over ``element``, written with it) or ``"armature"``
        (the robot's armature, not stored per element).
    units : str
        ``"1"`` or :data:`ELEMENT_UNITS_RULE`.
    long_name : str
        Its ``long_name`` in ``results.h5``.
    text : bool
        Strings, not numbers.
    stored : bool
        Written by :func:`gd_analyze.store.datasets.summary_dataset` (a coordinate or the
        armature is not).
    required : bool
        A results file must hold it; an optional column a file does not hold is absent from
        the view.
    nan_where_zero : bool
        Stored as NaN where the element is zero in every part (a ratio of round-off).
    round_off : str or None
        Its round-off flag variable: 1 where the value is round-off of the element's scale
        or the arm's (:func:`gd_analyze.ranking.ranking.is_round_off`).
    round_off_long_name : str
        That flag's ``long_name``.
    cli : CliShown or None
        Its column in the command line's table; None: not shown there.
    report : ReportShown or None
        Its column in the report's table; None: not shown there.
    """

    name: str
    field: str
    source: str
    units: str
    long_name: str
    text: bool = False
    stored: bool = True
    required: bool = True
    nan_where_zero: bool = False
    round_off: str | None = None
    round_off_long_name: str = ""
    cli: CliShown | None = None
    report: ReportShown | None = None


def _peak_flag(part: str) -> str:
    return (f"1 where the peak {part} part is round-off of the element's scale or the arm's "
            "(shown as \u2261 0), not data")


#: The ranking table's per-element columns, in the order both renderers show them (the
#: command line shows those with a ``cli``, the report those with a ``report``).
#: :func:`gd_analyze.store.datasets.summary_dataset` writes them (with a round-off flag where
#: one is named), the results view reads them, and
#: :meth:`gd_analyze.store.results_view.RankingTable.text` and the report render them, by
#: iterating this.
#:
#: Which new columns are 2-file changes: a column of ``source="ranking"`` whose value is a
#: function of what :class:`gd_analyze.ranking.ranking.RankingAccumulator` accumulates is one
#: entry here (and its ``Var`` constants above; ``required=False``, so that results files
#: written before it still read) plus, in ranking/ranking.py, its field of
#: :class:`gd_analyze.ranking.ranking.Ranking` and the one line of
#: :meth:`~gd_analyze.ranking.ranking.RankingAccumulator.result` that computes it. What is
#: accumulated (:mod:`gd_analyze.ranking.statistics`): per element, for each of x = tran,
#: rot + arm and tran + rot + arm, sum |x|, sum x^2 and peak |x|; peak |rot|; the element's
#: scale, its armature and the number of set points N. So, e.g., the RMS sqrt(sum x^2 / N)
#: or the mean |x| of any of the three, a share of two sums, a crest factor peak / RMS. No
#: other column is: another statistic or another series (the signed mean of x, a quantile,
#: the set point of the peak, a statistic of tau) also changes the compiled pass
#: (ranking/kernels.py and ranking/statistics.py), and a column of another source needs its
#: values brought to :func:`gd_analyze.store.datasets.summary_dataset` (store/datasets.py).
RANKING_COLUMNS: Final[tuple[RankingColumn, ...]] = (
    RankingColumn(Var.ELEMENT, "label", "coordinate", "1", "ranked element of D (i <= j) or h", text=True,
                  stored=False, cli=CliShown("element", "<8"),
                  report=ReportShown("element", "label", 0.8)),
    RankingColumn(Var.SHARE_TRAN, "share_tran", "ranking", "1",
                  "translational share sum|tran| / (sum|tran| + sum|rot|); NaN where the "
                  "element is zero in every part (round-off)", nan_where_zero=True,
                  cli=CliShown("share_tran", ">11", ".4f"),
                  report=ReportShown("translational share", "share", 0.9)),
    RankingColumn(Var.SHARE_ARM, "share_arm", "ranking", "1",
                  "armature share sum|arm| / (sum|tran| + sum|rot + arm|), diagonal of D only",
                  required=False,
                  report=ReportShown("armature share", "armature_share", 0.9)),
    RankingColumn(Var.DOMINANCE, "dominance", "ranking", "1",
                  "dominance class (translational, rotational, both, negligible)", text=True,
                  cli=CliShown("class", "<14", lead="  "),
                  report=ReportShown("class", "class", 1.2)),
    RankingColumn(Var.CHAPTER_DOMINANCE, "chapter_dominance", "chapter", "1",
                  "dominance reported in Sec. 3.4.1 for the chapter's PUMA 560 (empty unless "
                  "the robot is a PUMA 560)", text=True),
    RankingColumn(Var.CHOICE, "choice", "choices", "1",
                  "part kept by the simplified model (tran, rot, both, none; for the "
                  "recursive form both, or pruned where its dropped base-parameter terms "
                  "change the element)", text=True),
    RankingColumn(Var.PEAK_TRAN, "peak_tran", "ranking", ELEMENT_UNITS_RULE,
                  "peak |translational part| along the trajectory",
                  round_off=Var.PEAK_TRAN_ROUND_OFF,
                  round_off_long_name=_peak_flag("translational"),
                  report=ReportShown("peak |{X}|", "peak", 1, "tran")),
    RankingColumn(Var.PEAK_ROT, "peak_rot", "ranking", ELEMENT_UNITS_RULE,
                  "peak |rotational part| along the trajectory",
                  round_off=Var.PEAK_ROT_ROUND_OFF, round_off_long_name=_peak_flag("rotational"),
                  report=ReportShown("peak |{X}|", "peak", 1, "rot")),
    RankingColumn("peak_arm", "peak_arm", "armature", ELEMENT_UNITS_RULE,
                  "the armature on D's diagonal", stored=False, required=False,
                  report=ReportShown("peak |{X}|", "armature_peak", 1, "arm")),
    RankingColumn(Var.PEAK_TOTAL, "peak_total", "ranking", ELEMENT_UNITS_RULE,
                  "peak |translational + rotational| along the trajectory",
                  round_off=Var.PEAK_TOTAL_ROUND_OFF, round_off_long_name=_peak_flag("total"),
                  cli=CliShown("peak_total", ">12", ".4g"),
                  report=ReportShown("peak |{X}|", "peak", 1)),
    RankingColumn(Var.ELEMENT_SCALE, "scale", "ranking", ELEMENT_UNITS_RULE,
                  "scale of the negligibility test: peak sqrt(D_ii D_jj) or |tau_i|"),
    RankingColumn(Var.DOMINANCE_RIGID_LINKS, "rigid_dominance", "ranking", "1",
                  "dominance class of the rigid links alone: drives (armature, friction) left "
                  "out", text=True, required=False),
    RankingColumn(Var.ELEMENT_UNITS, "units", "coordinate", "1", "units of the element",
                  text=True, stored=False, cli=CliShown("units", "", lead="  "),
                  report=ReportShown("units", "units", 0.8)),
)
