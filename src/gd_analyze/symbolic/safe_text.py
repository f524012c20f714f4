"""Input text made safe for the comments of emitted C and Python source.

Robot names, file paths and descriptions come from input files and are hostile: a name holding
``*/`` would end the header comment of ``simplified_model.c`` and put its own code into the
model; one holding ``\"\"\"`` would do the same to a Python docstring. :func:`comment_safe` keeps
only characters that cannot end or extend a C block comment or a Python ``#`` comment, nor
open a string, and names the raw text by its SHA-256 so that what it replaced is still
identified. (HTML and PDF reports show the raw text: Jinja2 autoescape and literal strings.)
"""

from __future__ import annotations

import hashlib
import re
import string
from typing import Any

__all__ = ["comment_safe", "header_lines", "c_string", "python_string",
           "include_guard", "c_prefix", "check_prefix",
           "SAFE_CHARACTERS", "MAX_LENGTH", "DIGEST_LENGTH", "PREFIX_PATTERN"]

#: The characters kept: printable ASCII without ``*`` (``/*``, ``*/``), backslash (line splices,
#: escapes), ``?`` (the trigraph ``??/`` is a backslash), quotes and backquote (strings,
#: docstrings) and ``#`` (a comment or preprocessor line); no newline, carriage return, tab,
#: form feed or Unicode line separator.
SAFE_CHARACTERS = frozenset(string.ascii_letters + string.digits + " _-.,:;+=()[]{}<>@%&!~^|$/")

#: Longest sanitised text (the SHA-256 still names the whole of it).
MAX_LENGTH = 200
#: Length of the `` (sha256 <hex>)`` that ``comment_safe(text, digest=True)`` appends.
DIGEST_LENGTH = len(" (sha256 )") + 64


def comment_safe(text: str, digest: bool = False, limit: int = MAX_LENGTH) -> str:
    """The text with every character outside :data:`SAFE_CHARACTERS` replaced by ``_``.

    Parameters
    ----------
    text : str
        Any text, e.g. a robot name from a TOML file or a URDF ``<robot name>``.
    digest : bool, optional
        Append `` (sha256 <hex>)``: the SHA-256 of the raw text's UTF-8 bytes (lone surrogates
        escaped), which identifies it whatever was replaced.
    limit : int, optional
        Longest result before the digest (default :data:`MAX_LENGTH`).

    Returns
    -------
    str
        At most ``limit`` safe characters (longer text is cut and ends in ``...``),
        plus the digest if asked. It cannot contain ``*/``, ``/*``, ``\"\"\"``, ``'''``, a
        backslash, ``??/``, ``#`` or any line break, so it can stand in a C block comment, a
        C or Python line comment, or a Python string literal of either quote.

    Notes
    -----
    Own rule, not from the chapter: against code injection through the header of the
    emitted model. :func:`comment_safe` is idempotent.

    Examples
    --------
    >>> comment_safe('a */ int x; /* "b"')
    'a _/ int x; /_ _b_'
    >>> comment_safe("two-link", digest=True)[:33]
    'two-link (sha256 6dcdfcdfdcf5f341'
    """
    text = str(text)
    safe = "".join(ch if ch in SAFE_CHARACTERS else "_" for ch in text)
    if len(safe) > limit:
        safe = safe[:limit - 3] + "..."
    if not digest:
        return safe
    raw = text.encode("utf-8", "backslashreplace")
    return f"{safe} (sha256 {hashlib.sha256(raw).hexdigest()})"


def header_lines(header: dict[str, Any]) -> list[str]:
    """The lines ``key: value`` of an emitted file's header, each key and value made safe.

    Parameters
    ----------
    header : dict
        Header entries (any values; ``str`` of each is taken).

    Returns
    -------
    list of str
        One line per entry, through :func:`comment_safe` (no digest added: give the entries
        that come from input ``comment_safe(text, digest=True)`` beforehand; a value is cut
        only past :data:`MAX_LENGTH` plus :data:`DIGEST_LENGTH` characters, so such an entry
        keeps its digest whole).

    Examples
    --------
    >>> header_lines({"robot": "x */ y", "tolerance": 0.01})
    ['robot: x _/ y', 'tolerance: 0.01']
    """
    return [f"{comment_safe(k)}: {comment_safe(v, limit=MAX_LENGTH + DIGEST_LENGTH)}"
            for k, v in header.items()]


#: A prefix of the emitted C symbols: a letter, then letters, digits and underscores (never a
#: reserved identifier: no leading underscore), at most 64 characters.
PREFIX_PATTERN = re.compile(r"[A-Za-z][A-Za-z0-9_]{0,63}")


#: The characters a string literal of emitted code holds as they are (every other one is
#: escaped): no quote, backslash, ``?`` (trigraphs), ``%`` (printf) nor anything outside ASCII.
_LITERAL = frozenset(string.ascii_letters + string.digits + " _.-")


def c_string(text: str) -> str:
    """A C string literal of the exact UTF-8 bytes of ``text``.

    Parameters
    ----------
    text : str
        Any text, e.g. a URDF ``<joint name>`` (lone surrogates are written as their escapes).

    Returns
    -------
    str
        ``"..."``: letters, digits, space, ``_ . -`` as they are, every other byte as a
        three-digit octal escape (``\\ooo``, which never takes a following digit into it),
        so that distinct names give distinct literals and none can end the literal.

    Examples
    --------
    >>> print(c_string("a b"), c_string("a+b"), c_string('j"1'))
    "a b" "a\\053b" "j\\0421"
    """
    raw = str(text).encode("utf-8", "backslashreplace")
    return '"' + "".join(chr(b) if chr(b) in _LITERAL else f"\\{b:03o}" for b in raw) + '"'


def python_string(text: str) -> str:
    """A Python string literal of ``text`` exactly, in ASCII.

    Parameters
    ----------
    text : str
        Any text.

    Returns
    -------
    str
        ``"..."``: letters, digits, space, ``_ . -`` as they are, every other character as
        ``\\xhh``, ``\\uhhhh`` or ``\\Uhhhhhhhh``; ``eval`` of it gives ``text`` back.

    Examples
    --------
    >>> print(python_string("a+b"), python_string("\\u202e"))
    "a\\x2bb" "\\u202e"
    """
    def escape(ch):
        code = ord(ch)
        return (f"\\x{code:02x}" if code < 0x100 else f"\\u{code:04x}" if code < 0x10000
                else f"\\U{code:08x}")
    return '"' + "".join(ch if ch in _LITERAL else escape(ch) for ch in str(text)) + '"'


def include_guard(prefix: str, stem: str) -> str:
    """The include guard of a C header: the prefix and stem in capitals, and a short hash of
    the exact prefix, so that prefixes differing only in case (``arm_``, ``ARM_``) give
    headers that can be included together.

    Parameters
    ----------
    prefix : str
        A C identifier (:func:`check_prefix`).
    stem : str
        The file's stem, e.g. ``simplified_model``.

    Returns
    -------
    str
        E.g. ``ARM_SIMPLIFIED_MODEL_H_1A2B3C4D``: the first 8 hexadecimal digits of the
        SHA-256 of ``prefix + "/" + stem``.
    """
    digest = hashlib.sha256(f"{prefix}/{stem}".encode()).hexdigest()[:8].upper()
    return re.sub(r"[^A-Za-z0-9_]", "_", f"{prefix}{stem}_h".upper()) + f"_{digest}"


def c_prefix(name: str) -> str:
    """The default prefix of the emitted C symbols: a robot's name as a C identifier, plus ``_``.

    Parameters
    ----------
    name : str
        Any text (input: a robot's name).

    Returns
    -------
    str
        Runs of characters outside ``[A-Za-z0-9]`` become one ``_``, leading and trailing ones
        are dropped, ``gd_`` is put before a leading digit (``model`` stands for nothing left),
        cut to 40 characters, then ``_``: it matches :data:`PREFIX_PATTERN` whatever the name,
        so the name itself never becomes code.

    Examples
    --------
    >>> c_prefix("puma560"), c_prefix("560 arm */"), c_prefix("*/")
    ('puma560_', 'gd_560_arm_', 'model_')
    """
    core = re.sub(r"[^A-Za-z0-9]+", "_", str(name)).strip("_")[:40].strip("_") or "model"
    if core[0].isdigit():
        core = f"gd_{core}"[:40]
    return core + "_"


def check_prefix(prefix: str) -> str:
    """A prefix given by the user, checked.

    Parameters
    ----------
    prefix : str

    Returns
    -------
    str
        The prefix, unchanged.

    Raises
    ------
    ValueError
        If it does not match :data:`PREFIX_PATTERN` (a letter, then letters, digits and
        underscores, at most 64 characters).
    """
    if not isinstance(prefix, str) or not PREFIX_PATTERN.fullmatch(prefix):
        raise ValueError(f"the prefix {str(prefix)[:70]!r} is not a C identifier of a letter "
                         "then letters, digits and underscores (at most 64)")
    return prefix
