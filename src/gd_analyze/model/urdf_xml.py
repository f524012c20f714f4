"""The URDF's own text, read with the standard library, to check what Pinocchio's parser loaded.

Pinocchio reads a URDF file through urdfdom, which drops an ``<inertial>`` element it cannot
parse (a mass of ``"2,5"``, ``"2.5kg"`` or ``"nan"``, a centre of mass of ``nan``, an ``ixx`` of
``inf``, a missing ``<mass>`` or inertia attribute) with a message on the C stderr and goes on
with a massless link, or keeps the mass and loses the inertia tensor. Every check against
Pinocchio then passes on the same wrong model. This module reads the file itself
(:mod:`xml.etree.ElementTree`, with document type declarations refused so that no entity is
ever expanded), refuses every ``<inertial>`` that is present but broken, and compares the mass,
centre of mass and inertia tensor of each moving joint's body (the links carried by fixed
joints added in, as Pinocchio merges them) with the ones Pinocchio loaded. A link without an
``<inertial>`` is massless, as the URDF specification says (e.g. a frame link).

``<mimic>`` joints are not modelled (Pinocchio's ``mimic=False`` treats them as independent
joints): :func:`check_mimic` refuses a mimic joint on the chain, and one off the chain that
follows a chain joint; one off the chain that follows a locked joint is locked where its
``<mimic>`` puts it (its offset).
"""

from __future__ import annotations

import math
import re
import xml.etree.ElementTree as ET
from collections.abc import Iterable
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any
from xml.parsers import expat

import numpy as np

from ..errors import InputError
from .limits import LIMITS

if TYPE_CHECKING:                       # for the type hints only
    import pinocchio

__all__ = ["UrdfXml", "read_urdf_xml", "check_inertias", "check_mimic"]

#: A decimal number as urdfdom reads it, without surrounding blanks: no "nan", "inf",
#: hexadecimal, digit separators, decimal commas or units.
_NUMBER = re.compile(r"[+-]?(?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d+)?")

_INERTIA = ("ixx", "ixy", "ixz", "iyy", "iyz", "izz")

#: Relative tolerance of the comparison with Pinocchio's inertias (on sqrt(S_ii S_jj) of the
#: 6 x 6 spatial inertia S; the values differ only by rounding).
RTOL = 1e-9


@dataclass(frozen=True)
class UrdfXml:
    """What :func:`read_urdf_xml` read from a URDF file.

    Attributes
    ----------
    inertials : dict
        Link name -> None (no ``<inertial>``: massless) or ``(mass, xyz, rpy, I)``: mass [kg],
        centre of mass xyz [m] and rpy [rad] of the inertial frame, and I, ndarray shape (3, 3)
        [kg m^2] about the centre of mass in the inertial frame.
    joints : dict
        Joint name -> ``(type, parent link, child link, xyz, rpy, mimic)``; mimic is None or
        ``(mimicked joint, multiplier, offset)``.
    """

    inertials: dict
    joints: dict


class _DoctypeRefused(Exception):
    pass


def _refuse_doctype(*_args):
    raise _DoctypeRefused


def _parse_tree(raw, path):
    """The document's root element; a document type declaration (which could declare entities:
    "billion laughs") is refused before any of it is read."""
    guard = expat.ParserCreate()
    guard.StartDoctypeDeclHandler = _refuse_doctype
    guard.EntityDeclHandler = _refuse_doctype
    try:
        guard.Parse(raw, True)
        return ET.fromstring(raw)
    except _DoctypeRefused:
        raise InputError("a document type declaration (<!DOCTYPE ...>) is not accepted in a "
                         "URDF file (it could declare entities)", path) from None
    except (expat.ExpatError, ET.ParseError) as exc:
        raise InputError(f"not a valid URDF file: not well-formed XML ({exc})", path) from None


def _number(text, path, where):
    if text is None:
        raise InputError("missing", path, column=where)
    if not _NUMBER.fullmatch(text):
        raise InputError(f"not a number: {text!r}", path, column=where)
    value = float(text)
    if not math.isfinite(value):
        raise InputError(f"not a finite number: {text!r}", path, column=where)
    return value


def _vector(text, path, where):
    parts = text.split()
    if len(parts) != 3:
        raise InputError(f"needs 3 numbers, not {text!r}", path, column=where)
    return np.array([_number(p, path, where) for p in parts])


def _only(element, tag, path, where, required=True):
    found = element.findall(tag)
    if len(found) > 1:
        raise InputError(f"{len(found)} <{tag}> elements (URDF allows one)", path, column=where)
    if not found and required:
        raise InputError(f"no <{tag}> element", path, column=where)
    return found[0] if found else None


def _origin(element, path, where):
    """(xyz, rpy) of the ``<origin>`` child of an element (zeros where absent)."""
    origin = _only(element, "origin", path, f"{where} <origin>", required=False)
    return tuple(np.zeros(3) if origin is None or origin.get(key) is None else
                 _vector(origin.get(key), path, f"{where} <origin {key}>") for key in ("xyz", "rpy"))


def _inertial(link, name, path):
    where = f"link {name!r}"
    inertial = _only(link, "inertial", path, f"{where} <inertial>", required=False)
    if inertial is None:
        return None
    mass_el = _only(inertial, "mass", path, f"{where} <mass>")
    mass = _number(mass_el.get("value"), path, f"{where} <mass value>")
    if mass < 0:
        raise InputError(f"negative mass: {mass_el.get('value')!r}", path,
                         column=f"{where} <mass value>")
    xyz, rpy = _origin(inertial, path, f"{where} <inertial>")
    tensor = _only(inertial, "inertia", path, f"{where} <inertia>")
    v = {k: _number(tensor.get(k), path, f"{where} <inertia {k}>") for k in _INERTIA}
    I = np.array([[v["ixx"], v["ixy"], v["ixz"]],
                  [v["ixy"], v["iyy"], v["iyz"]],
                  [v["ixz"], v["iyz"], v["izz"]]])
    return mass, xyz, rpy, I


def _joint(joint, name, path):
    where = f"joint {name!r}"
    kind = joint.get("type")
    links = []
    for tag in ("parent", "child"):
        el = _only(joint, tag, path, where)
        if el.get("link") is None:
            raise InputError("missing", path, column=f"{where} <{tag} link>")
        links.append(el.get("link"))
    xyz, rpy = _origin(joint, path, where)
    _only(joint, "limit", path, f"{where} <limit>", required=kind in ("revolute", "prismatic"))
    mimic = None
    el = _only(joint, "mimic", path, f"{where} <mimic>", required=False)
    if el is not None:
        if el.get("joint") is None:
            raise InputError("missing", path, column=f"{where} <mimic joint>")
        mult = el.get("multiplier")
        off = el.get("offset")
        mimic = (el.get("joint"),
                 1.0 if mult is None else _number(mult, path, f"{where} <mimic multiplier>"),
                 0.0 if off is None else _number(off, path, f"{where} <mimic offset>"))
    return kind, links[0], links[1], xyz, rpy, mimic


def _named(root, tag, path):
    named = {}
    for el in root.findall(tag):
        name = el.get("name")
        if name is None:
            raise InputError(f"a <{tag}> without a name", path)
        if name in named:
            raise InputError(f"two <{tag}> elements named {name!r}", path)
        named[name] = el
    return named


def _check_size(root, path):
    """Refuse a URDF beyond :data:`~gd_analyze.model.limits.LIMITS`' ``urdf_links``,
    ``urdf_joints`` and ``urdf_depth``, before anything else reads it (Pinocchio's parser
    recurses once per tree level and overflows the C stack on a deep tree)."""
    links, joints = root.findall("link"), root.findall("joint")
    for what, found in (("links", links), ("joints", joints)):
        if len(found) > LIMITS[f"urdf_{what}"]:
            raise InputError(f"too large: {len(found):,} <{what[:-1]}> elements, at most "
                             f"{LIMITS[f'urdf_{what}']:,} are accepted", path)
    parent = {}
    for joint in joints:
        p, c = joint.find("parent"), joint.find("child")
        if p is not None and c is not None:
            if c.get("link") in parent:
                raise InputError(f"link {c.get('link')!r} is the child of two joints (a URDF's "
                                 "links form a tree)", path, column=f"joint {joint.get('name')!r}")
            parent[c.get("link")] = p.get("link")
    depth, limit = {}, LIMITS["urdf_depth"]
    for link in parent:
        path_up = []
        while link in parent and link not in depth:
            path_up.append(link)
            link = parent[link]
            if len(path_up) > len(parent):
                raise InputError(f"the joints form a loop through link {link!r}", path)
        d = depth.get(link, 0)
        for name in reversed(path_up):
            d += 1
            depth[name] = d
    deepest = max(depth.values(), default=0)
    if deepest > limit:
        raise InputError(f"too deep: a chain of {deepest:,} joints from the root link, at "
                         f"most {limit:,} are accepted", path)


def read_urdf_xml(raw: bytes, path: str) -> UrdfXml:
    """Read the links' inertials and the joints of a URDF file, refusing broken values.

    Parameters
    ----------
    raw : bytes
        The file's bytes.
    path : str
        The file, for the messages.

    Returns
    -------
    UrdfXml

    Raises
    ------
    InputError
        One line naming the file, the link or joint and the attribute: a document type
        declaration; XML that is not well-formed or whose root is not ``<robot>``; two links or
        joints of one name; an ``<inertial>`` without ``<mass value>`` or ``<inertia>``, or with
        a value (mass, the six inertia attributes, the origin's xyz and rpy) that is not a
        finite decimal number, or a negative mass; a joint origin that is not 3 finite numbers;
        a revolute or prismatic joint without ``<limit>`` (urdfdom would refuse it with
        messages of its own on the C stderr); several ``<inertial>``, ``<mass>``,
        ``<inertia>``, ``<origin>`` or ``<limit>`` in one place; more
        links or joints, or a deeper tree, than :data:`~gd_analyze.model.limits.LIMITS`
        accepts (``urdf_links``, ``urdf_joints``, ``urdf_depth``); joints that form a loop; a
        link that is the child of two joints.

    Notes
    -----
    Source: the URDF specification, wiki.ros.org/urdf/XML/link and wiki.ros.org/urdf/XML/joint.

    Examples
    --------
    >>> doc = read_urdf_xml(b'<robot name="r"><link name="a"><inertial><mass value="2.5kg"/>'
    ...                     b'</inertial></link></robot>', "r.urdf")
    Traceback (most recent call last):
    ...
    gd_analyze.errors.InputError: r.urdf: link 'a' <mass value>: not a number: '2.5kg'
    """
    root = _parse_tree(raw, path)
    if root.tag != "robot":
        raise InputError(f"not a valid URDF file: the root element is <{root.tag}>, not "
                         "<robot>", path)
    _check_size(root, path)
    inertials = {name: _inertial(el, name, path)
                 for name, el in _named(root, "link", path).items()}
    joints = {name: _joint(el, name, path) for name, el in _named(root, "joint", path).items()}
    return UrdfXml(inertials=inertials, joints=joints)


def _placement(pin, xyz, rpy):
    return pin.SE3(pin.rpy.rpyToMatrix(*rpy), np.asarray(xyz, float))


def _moved(pin, body, placement):
    """(m, h = m c, I about the origin) of a body given in a frame that ``placement`` (R, p)
    places in its parent frame, in the parent frame (Featherstone 2008, Eq. 2.66)."""
    m, h, I = body
    R, p = np.asarray(placement.rotation), np.asarray(placement.translation)
    Rh, P = R @ h, pin.skew(p)
    return m, Rh + m * p, R @ I @ R.T - pin.skew(Rh) @ P - P @ pin.skew(Rh) - m * P @ P


def _body_inertia(pin, doc, fixed, link):
    """The 6 x 6 spatial inertia of a link and every link hanging from it by fixed joints
    (``fixed``: parent link -> [(child link, placement)]), in the link's frame.

    numpy, not ``pinocchio.Inertia``: that refuses the slightly indefinite tensors some real
    URDF files hold (e.g. the TIAGo's antennas) where its parser loads them."""
    m, h, I = 0.0, np.zeros(3), np.zeros((3, 3))
    stack = [(link, pin.SE3.Identity())]
    seen = set()
    while stack:
        name, placement = stack.pop()
        if name in seen:  # a loop: urdfdom refuses the file before this runs
            continue
        seen.add(name)
        value = doc.inertials.get(name)
        if value is not None:
            mass, c, rpy, Ic = value
            R = np.asarray(pin.rpy.rpyToMatrix(*rpy))
            own = (mass, mass * c, R @ Ic @ R.T - mass * pin.skew(c) @ pin.skew(c))
            dm, dh, dI = _moved(pin, own, placement)
            m, h, I = m + dm, h + dh, I + dI
        stack.extend((child, placement * p) for child, p in fixed.get(name, ()))
    H = pin.skew(h)
    return np.block([[m * np.eye(3), H.T], [H, I]])


def check_inertias(doc: UrdfXml, model: pinocchio.Model, path: str) -> None:
    """Check that Pinocchio loaded the file's inertias: each moving joint's body, with the
    links carried by fixed joints, against ``model.inertias``.

    Parameters
    ----------
    doc : UrdfXml
        The file as :func:`read_urdf_xml` read it.
    model : pinocchio.Model
        The model Pinocchio built from the same bytes.
    path : str
        The file, for the messages.

    Raises
    ------
    InputError
        Naming the joint's child link, if the spatial inertias differ by more than
        :data:`RTOL` times sqrt(S_ii S_jj) (at least 1e-3 max |S_ij|) in any element.

    Notes
    -----
    The 6 x 6 spatial inertia S = [[m 1, m [c]^T], [m [c], I_c + m [c]^T [c]]]
    (Featherstone, *Rigid Body Dynamics Algorithms*, 2008, Eq. 2.63), each link's moved into
    its joint's frame by the fixed placements in between.
    """
    import pinocchio as pin

    fixed: dict[str, list[tuple[str, Any]]] = {}
    for kind, parent, child, xyz, rpy, _ in doc.joints.values():
        if kind == "fixed":
            fixed.setdefault(parent, []).append((child, _placement(pin, xyz, rpy)))
    for name, (kind, _, child, *_rest) in doc.joints.items():
        j = model.getJointId(name)
        if kind == "fixed" or j >= model.njoints:
            continue  # not a moving joint of the model (merged, or a parse Pinocchio does not do)
        ours = _body_inertia(pin, doc, fixed, child)
        theirs = np.asarray(model.inertias[j].matrix())
        d = np.sqrt(np.abs(np.diag(ours)))
        # floor: an element whose sqrt(S_ii S_jj) is 0 (an unphysical tensor with a zero
        # moment and products) is still compared on the body's own scale, with room for rounding
        scale = np.maximum(np.outer(d, d), 1e-3 * np.abs(ours).max())
        if not (np.abs(ours - theirs) <= RTOL * scale).all():
            m = model.inertias[j]
            raise InputError(
                f"Pinocchio loaded mass {m.mass:.6g} kg, centre of mass "
                f"{np.round(m.lever, 6).tolist()} m for this body, not what the file gives "
                f"(mass {ours[0, 0]:.6g} kg): its parser read the <inertial> differently", path,
                column=f"link {child!r} <inertial>")


def check_mimic(doc: UrdfXml, chain: Iterable[str], locked: Iterable[str],
                path: str) -> dict[str, float]:
    """Refuse ``<mimic>`` joints that the chain model would get wrong, and give the position
    of each locked one.

    Parameters
    ----------
    doc : UrdfXml
        The file as :func:`read_urdf_xml` read it.
    chain, locked : iterable of str
        The names of the chain's joints and of the moving joints locked off it.
    path : str
        The file, for the messages.

    Returns
    -------
    dict
        Locked mimic joint name -> its position [rad or m] where it is not 0: ``offset +
        multiplier * position`` of the joint it follows (URDF specification), which is locked
        too, at 0 unless it is a mimic joint itself.

    Raises
    ------
    InputError
        Naming the joint: a mimic joint on the chain (gd-analyze does not model mimic joints);
        a locked mimic joint that follows a chain joint (it would move with the chain).
    """
    mimics = {name: mimic for name, (*_, mimic) in doc.joints.items() if mimic is not None}
    chain, locked, at = set(chain), set(locked), dict.fromkeys(mimics, 0.0)
    for _ in mimics:    # a mimic of a mimic: its leader's position first (one round a level)
        at = {name: off + mult * at.get(led, 0.0) for name, (led, mult, off) in mimics.items()}
    for name, (followed, _, _) in mimics.items():
        if name in chain:
            why = f"a mimic joint on the chain (it follows {followed!r})"
        elif name in locked and followed in chain:
            why = f"locked off the chain, but it follows the chain joint {followed!r}"
        else:
            continue
        raise InputError(f"{why}: gd-analyze does not model <mimic> joints", path,
                         column=f"joint {name!r} <mimic>")
    return {name: float(q) for name, q in at.items() if name in locked and q != 0.0}
