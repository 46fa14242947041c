"""docs/architecture.md's two tables against the code: every import between granular_tools'
modules against the package's "may import" table, and every #include "granular_core/<folder>/..."
of granular_core's src/, include/ and test/ against the core's "may include" table. The doc is
the only list: a new module, package or folder needs its row before its code passes."""
import ast
import pathlib
import re

REPO_ROOT = pathlib.Path(__file__).resolve().parents[4]
DOC = REPO_ROOT / "docs" / "architecture.md"
PACKAGE = REPO_ROOT / "ros_ws" / "src" / "granular_tools" / "src" / "granular_tools"
CORE = REPO_ROOT / "ros_ws" / "src" / "granular_core"
CORE_TABLE = "| folder | owns | may include |"
TOOLS_TABLE = "| floor | module or package | owns | may import |"
MAX_FLOORS = 4
TESTS_ALSO = "tests also:"


def table_rows(header):
    """The cells of each row of the doc's table whose header line is `header`."""
    lines = DOC.read_text(encoding="utf-8").splitlines()
    assert header in lines, f"{DOC} has no table headed {header}"
    rows = []
    for line in lines[lines.index(header) + 2:]:
        if not line.startswith("|"):
            break
        rows.append([cell.strip() for cell in line.strip().strip("|").split("|")])
    return rows


def listed(cell):
    """The items of a comma-separated cell, parenthesised remarks and backticks dropped."""
    plain = re.sub(r"\([^)]*\)", "", cell).replace("`", "")
    return {item.strip() for item in plain.split(",") if item.strip()}


# ----------------------------------------------------------------------------- granular_core

def core_rules():
    """{folder: (folders its code may include, folders its tests may include)}; the root's
    headers are folder ""."""
    rows = []
    for first, _, may in table_rows(CORE_TABLE):
        folder = re.match(r"`([a-z_]+)/`", first)
        code, _, tests = may.partition(";")
        tests = tests.strip()
        tests = tests[len(TESTS_ALSO):] if tests.startswith(TESTS_ALSO) else ""
        rows.append((folder.group(1) if folder else "", listed(code), listed(tests)))
    folders = [folder for folder, _, _ in rows]
    rules = {}
    for index, (folder, code, tests) in enumerate(rows):
        above = set(folders[:index]) if "everything above" in code else set()
        allowed = (code & set(folders)) | above | {folder}
        rules[folder] = (allowed, allowed | (tests & set(folders)))
    return rules


INCLUDE = re.compile(r'^\s*#\s*include\s+"granular_core/([^/"]+)/', re.MULTILINE)


def include_breaches(folder, text, in_tests, rules):
    """The folders `text` (a file of `folder`) includes but may not."""
    code, tests = rules[folder]
    allowed = tests if in_tests else code
    return sorted(set(INCLUDE.findall(text)) - allowed)


def core_files():
    """(folder, in tests, path) of every C++ file of src/, include/granular_core/ and test/."""
    for root, in_tests in ((CORE / "src", False), (CORE / "include" / "granular_core", False),
                           (CORE / "test", True)):
        for path in sorted(root.rglob("*")):
            if path.suffix in (".h", ".hpp", ".cpp") and path.is_file():
                parts = path.relative_to(root).parts
                yield (parts[0] if len(parts) > 1 else ""), in_tests, path


def test_every_core_folder_has_a_row():
    rules = core_rules()
    files = list(core_files())
    assert len({folder for folder, _, _ in files}) > 10, f"{CORE}: the layers are not there"
    missing = sorted({f"{folder} ({path.relative_to(CORE)})"
                      for folder, _, path in files if folder not in rules})
    assert not missing, f"folders without a row in {DOC}'s table: {missing}"


def test_every_core_include_is_one_the_table_allows():
    rules = core_rules()
    breaches = [f"{path.relative_to(CORE)} includes {', '.join(found)}"
                for folder, in_tests, path in core_files() if folder in rules
                for found in [include_breaches(folder, path.read_text(encoding="utf-8"),
                                               in_tests, rules)] if found]
    assert not breaches, f"includes {DOC}'s table does not allow:\n" + "\n".join(breaches)


def test_the_include_check_catches_a_forbidden_include():
    rules = core_rules()
    text = '#include "granular_core/geometry/oriented_box.h"\n'
    assert include_breaches("ground", text, False, rules) == []
    text += '#include <vector>\n  #include "granular_core/runs/extract_run.h"\n'
    assert include_breaches("ground", text, False, rules) == ["runs"]
    online_test = '#include "granular_core/runs/classify_registration_run.h"\n'
    assert include_breaches("online", online_test, True, rules) == []
    assert include_breaches("online", online_test, False, rules) == ["runs"]


# ----------------------------------------------------------------------------- granular_tools

def tools_rows():
    """[(floor, name, names it may import)]: a name is a module without .py or a package."""
    rows = []
    for floor, first, _, may in table_rows(TOOLS_TABLE):
        name = re.match(r"`([a-z_]+)(?:\.py|/)`", first)
        assert name, f"{DOC}: no module or package in {first!r}"
        rows.append((floor, name.group(1), listed(may)))
    return rows


def tools_rules():
    """{name: the names it may import, its own included}."""
    rows = tools_rows()
    floors = list(dict.fromkeys(floor for floor, _, _ in rows))
    named = {"the ground floor": floors[0], "the stages": floors[1]}
    rules = {}
    for floor, name, may in rows:
        allowed = {name}
        for item in may - {"nothing"}:
            if item in named:
                allowed |= {other for f, other, _ in rows if f == named[item]}
            else:
                assert item in {other for _, other, _ in rows}, \
                    f"{DOC}: {name} may import {item!r}, which has no row"
                allowed.add(item)
        rules[name] = allowed
    return rules


def test_the_package_has_at_most_four_floors_and_no_arrow_up():
    rows = tools_rows()
    floors = list(dict.fromkeys(floor for floor, _, _ in rows))
    assert len(floors) <= MAX_FLOORS, floors
    rules = tools_rules()
    position = {name: (floors.index(floor), index) for index, (floor, name, _) in enumerate(rows)}
    for floor, name, _ in rows:
        for other in rules[name] - {name}:
            # A lower floor, or on its own floor a row listed above it (a fixed order).
            assert position[other] < position[name], \
                f"{name} ({floor}) may import {other}, which is not below it"


def module_name(path):
    """granular_tools.a.b of a file of the package."""
    parts = path.relative_to(PACKAGE.parent).with_suffix("").parts
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


def imported_modules(name, source, is_package=False):
    """The granular_tools modules (dotted) that `source`, the code of module `name`, imports,
    at module level or inside functions."""
    found = set()
    for node in ast.walk(ast.parse(source)):
        if isinstance(node, ast.Import):
            found |= {alias.name for alias in node.names}
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                base = name.split(".")
                base = base[:len(base) - node.level + (1 if is_package else 0)]
                target = ".".join(base + ([node.module] if node.module else []))
            else:
                target = node.module or ""
            # `from . import progress` imports a module; `from .x import f` imports .x.
            found |= {f"{target}.{alias.name}" for alias in node.names} | {target}
    return {module for module in found if module.startswith("granular_tools.")}


def row_of(module):
    """The table's name for a dotted module: its top-level module or package."""
    return module.split(".")[1]


def import_breaches(name, source, rules, is_package=False):
    allowed = rules[row_of(name)]
    return sorted({row_of(module) for module in imported_modules(name, source, is_package)}
                  - allowed)


def tools_modules():
    for path in sorted(PACKAGE.rglob("*.py")):
        name = module_name(path)
        if name != "granular_tools":
            yield name, path


def test_every_module_of_granular_tools_has_a_row():
    rules = tools_rules()
    rows = {row_of(name) for name, _ in tools_modules()}
    assert {"geometry", "runners", "labelling"} <= rows, f"{PACKAGE}: the modules are not there"
    missing = sorted(rows - set(rules))
    assert not missing, f"modules or packages without a row in {DOC}'s table: {missing}"


def test_every_import_in_granular_tools_is_one_the_table_allows():
    rules = tools_rules()
    breaches = [f"{name} imports {', '.join(found)}" for name, path in tools_modules()
                if row_of(name) in rules
                for found in [import_breaches(name, path.read_text(encoding="utf-8"), rules,
                                              path.name == "__init__.py")] if found]
    assert not breaches, f"imports {DOC}'s table does not allow:\n" + "\n".join(breaches)


def test_the_import_check_catches_a_forbidden_import():
    rules = tools_rules()
    assert import_breaches("granular_tools.frames_folder", "from .geometry import Cuboid",
                           rules) == []
    assert import_breaches("granular_tools.geometry", "from .frames_folder import stamp_name",
                           rules) == ["frames_folder"]
    assert import_breaches("granular_tools.evaluation.report",
                           "def f():\n    from ..runners import stages\n", rules) == ["runners"]
    assert import_breaches("granular_tools.kitti", "import granular_tools.simulation.recorder",
                           rules) == ["simulation"]
    assert import_breaches("granular_tools.labelling.node", "from ..kitti import Box\n"
                           "from . import session", rules) == []
