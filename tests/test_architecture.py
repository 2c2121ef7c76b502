"""The core crate's rooms stay rooms: no import cycle between sibling modules of
crates/raster/src, no lighting code outside lighting/, no fuzzing code in the default build.

A module is a file or a directory; `a` imports `b` when a file of `a` names `crate::b` or, for
siblings inside a directory, `super::b`. A parent's mod.rs and its children are not siblings
(the parent declares its children; they read its shared types)."""

import re
from pathlib import Path

SRC = Path(__file__).resolve().parent.parent / "crates" / "raster" / "src"


def _module_of(path: Path, base: Path) -> str:
    rel = path.relative_to(base)
    return rel.parts[0].removesuffix(".rs")


def _edges(base: Path, prefix: str) -> dict[str, set[str]]:
    """Imports between the modules directly under `base` (files and directories)."""
    names = {p.name.removesuffix(".rs") for p in base.iterdir() if p.suffix == ".rs" or p.is_dir()}
    names -= {"mod", "lib"}
    edges: dict[str, set[str]] = {n: set() for n in names}
    pattern = re.compile(rf"\b{prefix}::(\w+)")
    for path in base.rglob("*.rs"):
        if path.parent == base and path.name in ("mod.rs", "lib.rs"):
            continue
        # Code only: comments may name any module, and test modules may reach anywhere.
        src = path.read_text().split("#[cfg(test)]")[0]
        src = "\n".join(line.split("//")[0] for line in src.splitlines())
        here = _module_of(path, base)
        inner = len(path.relative_to(base).parts) > 1
        for target in pattern.findall(src):
            # `super::x` from a file nested deeper names its own directory's sibling.
            if prefix == "super" and inner:
                continue
            if target in names and target != here:
                edges[here].add(target)
    return edges


def _cycles(edges: dict[str, set[str]]) -> list[list[str]]:
    found = []
    state: dict[str, int] = {}

    def visit(n: str, stack: list[str]) -> None:
        state[n] = 1
        for m in sorted(edges.get(n, ())):
            if state.get(m) == 1:
                found.append([*stack[stack.index(m) :], m])
            elif m not in state:
                visit(m, [*stack, m])
        state[n] = 2

    for n in sorted(edges):
        if n not in state:
            visit(n, [n])
    return found


def test_no_import_cycle_between_top_level_modules():
    assert _cycles(_edges(SRC, "crate")) == []


def test_no_import_cycle_between_siblings_in_any_directory():
    for d in [p for p in SRC.rglob("*") if p.is_dir()]:
        assert _cycles(_edges(d, "super")) == [], d


def test_lighting_lives_in_its_room():
    # The equation's pieces are defined only in lighting/.
    for path in SRC.rglob("*.rs"):
        if "lighting" in path.parts:
            continue
        src = path.read_text()
        for definition in (
            "fn pow01",
            "fn shade_lanes",
            "fn terms_lanes",
            "cos_cutoff",
            "fn attenuation(",
        ):
            assert definition not in src, f"{path.relative_to(SRC)} defines {definition}"


def test_fuzz_bodies_are_not_in_the_default_build():
    lib = (SRC / "lib.rs").read_text()
    assert '#[cfg(feature = "fuzzing")]\n#[doc(hidden)]\npub mod fuzzing;' in lib
