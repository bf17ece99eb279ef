"""The cffi declarations (geom/_ffi.py) against the public headers: every
declared function, struct and enum must be identical to the header's (after
removing comments and normalising whitespace), every function must be
exported by the loaded library, and the macros the declarations use must
have the headers' values. This catches drift between the C API and the
bindings."""

import glob
import os
import re

import pytest

from geom import _ffi


def _strip(text):
    text = re.sub(r"/\*.*?\*/", " ", text, flags=re.S)
    text = re.sub(r"//[^\n]*", " ", text)
    text = re.sub(r"^\s*#.*$", " ", text, flags=re.M)
    text = re.sub(r"\bGEOM_API\b", " ", text)
    return text.replace('extern "C" {', " ")


def _norm(decl):
    decl = re.sub(r"\s+", " ", decl).strip()
    return re.sub(r"\s*([(){}\[\],;*])\s*", r"\1", decl)


def declarations(text, unparsed=None):
    """{name: (kind, normalised declaration)} of the top-level declarations:
    functions, typedef'd structs and enums, function pointer typedefs and
    opaque typedefs. Other declarations are appended to `unparsed`."""
    text = _strip(text)
    out = {}
    depth = 0
    start = 0
    for i, ch in enumerate(text):
        if ch == "{":
            depth += 1
        elif ch == "}":
            depth -= 1
        elif ch == ";" and depth == 0:
            decl = re.sub(r"\s+", " ", text[start:i + 1]).strip().lstrip("} ").strip()
            start = i + 1
            m = (re.match(r"typedef (?:struct|enum) \w+ ?\{.*\} ?(\w+) ?;$", decl)
                 or re.match(r"typedef (?:struct|enum) \w+ (\w+);$", decl)
                 or re.match(r"typedef [^(]*\(\*(\w+)\)\(.*\);$", decl))
            if m:
                out[m.group(1)] = ("type", _norm(decl))
                continue
            m = re.match(r"[^(]*?\b(geom_\w+) ?\(", decl)
            if m:
                out[m.group(1)] = ("function", _norm(decl))
            elif decl and unparsed is not None:
                unparsed.append(decl)
    return out


@pytest.fixture(scope="module")
def header_decls(include_dir):
    decls = {}
    files = sorted(glob.glob(os.path.join(include_dir, "*.h")))
    assert files, "no headers in %s" % include_dir
    for path in files:
        module = os.path.basename(path)[:-2]
        with open(path, encoding="utf-8") as f:
            for name, (kind, decl) in declarations(f.read()).items():
                decls.setdefault(name, (module, kind, decl))
    return decls


def _binding_decls():
    out = []
    for module in _ffi.MODULE_ORDER:
        for name, (kind, decl) in declarations(_ffi.CDEFS[module]).items():
            out.append((module, name, kind, decl))
    return out


BINDINGS = _binding_decls()


def test_declarations_were_found():
    # Every statement of the cdefs must be recognised (and so compared with
    # the headers below): nothing is declared that escapes the check.
    unparsed = []
    names = []
    for module in _ffi.MODULE_ORDER:
        names += list(declarations(_ffi.CDEFS[module], unparsed))
    assert unparsed == []
    assert len(names) == len(set(names)) == len(BINDINGS)
    assert sum(1 for b in BINDINGS if b[2] == "function") > 130


@pytest.mark.parametrize("module,name,kind,decl", BINDINGS, ids=[b[1] for b in BINDINGS])
def test_declaration_matches_header(header_decls, module, name, kind, decl):
    assert name in header_decls, "%s is bound but not declared in any public header" % name
    hmod, hkind, hdecl = header_decls[name]
    assert hmod == module, "%s is declared in %s.h, bound under %s" % (name, hmod, module)
    assert hkind == kind
    assert decl == hdecl, "declaration of %s differs from the header" % name


@pytest.mark.parametrize("module,name", [(b[0], b[1]) for b in BINDINGS if b[2] == "function"],
                         ids=[b[1] for b in BINDINGS if b[2] == "function"])
def test_function_is_exported(module, name):
    if not _ffi.has_module(module):
        pytest.skip("module %s not in this library" % module)
    assert hasattr(_ffi.lib, name), "%s missing from %s" % (name, _ffi.library_path)


def test_macros_match_headers(include_dir):
    text = ""
    for path in glob.glob(os.path.join(include_dir, "*.h")):
        with open(path, encoding="utf-8") as f:
            text += f.read()
    for name, value in _ffi.MACROS.items():
        m = re.search(r"#define %s\s+(\d+)\b" % name, text)
        assert m, name
        assert int(m.group(1)) == value


def test_every_module_is_bound(include_dir):
    # A new public header needs a section in the bindings (even if small).
    headers = {os.path.basename(p)[:-2] for p in glob.glob(os.path.join(include_dir, "*.h"))}
    assert headers <= set(_ffi.MODULE_ORDER), headers - set(_ffi.MODULE_ORDER)
