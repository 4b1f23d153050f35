"""No function over its length limit, outside the exemptions named here with their reason.

Limits: 80 lines for a Python function of the toolkit (mdbridge, dna_models, the `dnarod`
folder workflows/) and of bench/ and scripts/; 60 lines in a command module
(workflows/commands/: a command parses, calls the library and prints); 80 lines for a C++
function of rodcore/, bench/ and fuzz/. A function's length runs from its `def` (C++: the
line of its name) to its last line, docstring and comments included. Numeric kernels,
bindings and registries may be longer: each is named in EXEMPT with why. An exemption that
no longer names a long function fails too, so the list stays true.

Python functions are read with `ast`; C++ functions by matching braces in the source with
comments, strings and preprocessor lines blanked (a function is a brace block at namespace
or class scope whose head holds a parameter list). Each reader has a control: a planted
long function must be caught.
"""
from __future__ import annotations

import ast
import re
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
PY_FOLDERS = ("mdbridge", "dna_models", "workflows", "bench", "scripts")
CXX_FOLDERS = ("rodcore", "bench", "fuzz")
CXX_SUFFIXES = (".cpp", ".hpp", ".inc", ".h")
LIMIT = 80
COMMAND_LIMIT = 60
COMMANDS = "workflows/commands/"

# "path::qualified name": why it may be longer
EXEMPT = {
    # the `dnarod build-md` option table: one add_argument per option (a registry)
    "workflows/commands/build_md.py::add_arguments": "registry: the option table of build-md",
    # C++ numeric kernels: one pass over the grid, no allocation (docs/architecture.md)
    "rodcore/src/rhs.cpp::rod_kernel": "numeric kernel: the right-hand side of Eqs (11)-(14), one fused loop",
    "rodcore/src/thermal.cpp::add_thermal_sample": "numeric kernel: the exact Boltzmann sample, mode by mode",
    "rodcore/src/contact.cpp::SelfContact::forces": "numeric kernel: the self-contact pair forces",
    # bindings
    "rodcore/python/module.cpp::PYBIND11_MODULE": "bindings: the Python module rodcore",
    "rodcore/python/module.cpp::bind_topology": "bindings: rodcore.topology",
    # registries
    "rodcore/src/scene/initial_conditions.cpp::build_kinds": "registry: every initial.kind with its keys",
    "rodcore/src/scene/h5_output.cpp::write_scene_attributes": "registry: the attributes of the output file",
}


# -- Python ---------------------------------------------------------------------------------------

def python_functions(path: Path, rel: str) -> list[tuple[str, int, int]]:
    """(qualified name, first line, length) of every function of a Python file."""
    out = []

    def visit(node, prefix):
        for ch in ast.iter_child_nodes(node):
            if isinstance(ch, (ast.FunctionDef, ast.AsyncFunctionDef)):
                out.append((prefix + ch.name, ch.lineno, ch.end_lineno - ch.lineno + 1))
                visit(ch, prefix + ch.name + ".")
            elif isinstance(ch, ast.ClassDef):
                visit(ch, prefix + ch.name + ".")
            else:
                visit(ch, prefix)
    visit(ast.parse(path.read_text(), rel), "")
    return out


# -- C++ ------------------------------------------------------------------------------------------

def _blank(text: str) -> str:
    return re.sub(r"[^\n]", " ", text)


def strip_cxx(text: str) -> str:
    """TEXT with comments, string and character literals and preprocessor lines blanked
    (newlines kept, so line numbers stay)."""
    out, i, n = [], 0, len(text)
    while i < n:
        c = text[i]
        if text.startswith("//", i):
            j = text.find("\n", i)
            j = n if j < 0 else j
        elif text.startswith("/*", i):
            j = text.find("*/", i + 2)
            j = n if j < 0 else j + 2
        elif text.startswith('R"', i) and re.match(r'R"([^(\s]*)\(', text[i:]):
            delim = re.match(r'R"([^(\s]*)\(', text[i:]).group(1)
            j = text.find(")" + delim + '"', i) + len(delim) + 2
        elif c in "\"'":
            j = i + 1
            while j < n and text[j] != c:
                j += 2 if text[j] == "\\" else 1
            out.append(c + _blank(text[i + 1:j]) + c)
            i = j + 1
            continue
        elif c == "#" and (i == 0 or text[i - 1] == "\n"):
            j = i
            while True:
                k = text.find("\n", j)
                k = n if k < 0 else k
                if k >= n or text[k - 1] != "\\":
                    break
                j = k + 1
            j = k
        else:
            out.append(c)
            i += 1
            continue
        out.append(_blank(text[i:j]))
        i = j
    return "".join(out)


def _closing(s: str, i: int) -> int:
    depth = 0
    for j in range(i, len(s)):
        if s[j] == "{":
            depth += 1
        elif s[j] == "}":
            depth -= 1
            if depth == 0:
                return j
    return len(s) - 1


def _name(head: str) -> tuple[str, int]:
    """The function's (qualified) name in a definition's head, and its offset in the head."""
    depth = 0
    for k, ch in enumerate(head):
        if ch == "(" and depth == 0:
            m = re.search(r"(operator\s*\S+|[~\w:]+)\s*(<[^()]*>)?\s*$", head[:k])
            return (m.group(1) if m else "?"), k
        if ch in "<[":
            depth += 1
        elif ch in ">]":
            depth = max(0, depth - 1)
    return "?", 0


def cxx_functions(path: Path) -> list[tuple[str, int, int]]:
    """(qualified name, first line, length) of every function defined at namespace or class
    scope of a C++ file (lambdas and local classes count with the function around them)."""
    s = strip_cxx(path.read_text())
    out: list[tuple[str, int, int]] = []

    def scan(a: int, b: int, prefix: str) -> None:
        i = head_start = a
        while i < b:
            if s[i] in ";}":
                head_start = i = i + 1
                continue
            if s[i] != "{":
                i += 1
                continue
            head = s[head_start:i]
            h = " ".join(head.split())
            end = _closing(s, i)
            if re.search(r"\bnamespace\b|\bextern\s*$", h) and "(" not in h:
                scan(i + 1, end, prefix)
            elif re.search(r"\b(class|struct|union)\b", h) and "(" not in h:
                m = re.search(r"\b(?:class|struct|union)\s+(?:\w+\s+)*?([\w:]+)\s*(?:final\s*)?(?::[^:]|$)", h)
                scan(i + 1, end, prefix + (m.group(1) + "::" if m else ""))
            elif ")" in h and not re.search(r"=\s*$|\benum\b", h):
                tail = h[h.rfind(")") + 1:]
                if re.match(r"\s*(noexcept\s*)?:(?!:)", tail) and re.search(r"[\w>]\s*$", h):
                    i = end + 1               # braces of a member initialiser: the head goes on
                    continue
                name, k = _name(head)
                first = s.count("\n", 0, head_start + k) + 1
                out.append((prefix + name, first, s.count("\n", 0, end) + 1 - first + 1))
            i = head_start = end + 1
    scan(0, len(s), "")
    return out


# -- the rule -------------------------------------------------------------------------------------

def long_functions(root: Path) -> dict[str, str]:
    """'path::name' -> 'N lines (limit L), path:line' of every function over its limit."""
    found = {}
    for folder in PY_FOLDERS:
        for f in sorted((root / folder).rglob("*.py")):
            rel = f.relative_to(root).as_posix()
            limit = COMMAND_LIMIT if rel.startswith(COMMANDS) else LIMIT
            for name, line, n in python_functions(f, rel):
                if n > limit:
                    found[f"{rel}::{name}"] = f"{n} lines (limit {limit}), {rel}:{line}"
    for folder in CXX_FOLDERS:
        for f in sorted((root / folder).rglob("*")):
            if f.suffix in CXX_SUFFIXES and f.is_file():
                rel = f.relative_to(root).as_posix()
                for name, line, n in cxx_functions(f):
                    if n > LIMIT:
                        found[f"{rel}::{name}"] = f"{n} lines (limit {LIMIT}), {rel}:{line}"
    return found


def test_no_function_over_its_limit():
    over = {k: v for k, v in long_functions(ROOT).items() if k not in EXEMPT}
    assert not over, "split these (or, for a kernel, binding or registry, name it in EXEMPT with why):\n" \
        + "\n".join(f"  {k}: {v}" for k, v in sorted(over.items()))


def test_every_exemption_names_a_long_function():
    found = long_functions(ROOT)
    stale = sorted(k for k in EXEMPT if k not in found)
    assert not stale, f"exemptions that name no function over the limit (remove them): {stale}"


# -- controls -------------------------------------------------------------------------------------

def test_control_a_long_python_function_is_caught(tmp_path):
    body = "\n".join(f"    x{i} = {i}" for i in range(80))
    (tmp_path / "mdbridge").mkdir()
    method = body.replace("\n", "\n    ")
    (tmp_path / "mdbridge" / "planted.py").write_text(f"class A:\n    def f(self):\n    {method}\n"
                                                      "\n\ndef short():\n    return 1\n")
    (tmp_path / "workflows" / "commands").mkdir(parents=True)
    (tmp_path / "workflows" / "commands" / "cmd.py").write_text("def run(args):\n" + "\n".join(
        f"    print({i})" for i in range(60)) + "\n")
    found = long_functions(tmp_path)
    assert set(found) == {"mdbridge/planted.py::A.f", "workflows/commands/cmd.py::run"}, found
    assert found["workflows/commands/cmd.py::run"].startswith("61 lines (limit 60)")


def test_control_a_long_cxx_function_is_caught(tmp_path):
    (tmp_path / "rodcore").mkdir()
    lines = "\n".join(f'  x += {i};  // "}}" {{' for i in range(80))
    (tmp_path / "rodcore" / "planted.cpp").write_text(
        "#include <string>\n#define BRACE {\nnamespace rodcore {\nstruct S {\n  int a{1};\n"
        "  S(int b) : a{b} {}\n  double f() const;\n};\n"
        f"double S::f() const {{\n  double x = 0;\n{lines}\n  return x;\n}}\n"
        "int short_one(int y) {\n  auto g = [](int z) { return z; };\n  return g(y);\n}\n}  // namespace rodcore\n")
    found = cxx_functions(tmp_path / "rodcore" / "planted.cpp")
    names = {n: length for n, _, length in found}
    assert names == {"S::S": 1, "S::f": 84, "short_one": 4}, names
    assert list(long_functions(tmp_path)) == ["rodcore/planted.cpp::S::f"]
