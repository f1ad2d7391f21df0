"""The shape of the package that the consolidation fixed: code that says why (no issue numbers), modules small
enough to read, few long functions. Counted from the source, so a later change that breaks a limit fails here."""

from __future__ import annotations

import ast
import re
from pathlib import Path

from tests.conftest import ROOT, package_trees

PACKAGE = ROOT / "planner"
#: the limits: a module's lines, a function's lines, and how many functions may pass that
MODULE_LINES, FUNCTION_LINES, LONG_FUNCTIONS = 400, 80, 5


def _modules() -> list[Path]:
    return sorted(PACKAGE.rglob("*.py"))


def test_no_issue_numbers_in_the_package():
    """Issue numbers belong in commit messages, not in docstrings, comments or help text."""
    found = [
        f"{p.relative_to(ROOT)}:{n}"
        for p in _modules()
        for n, line in enumerate(p.read_text().splitlines(), 1)
        if re.search(r"\bissues? \d+", line, re.IGNORECASE)
    ]
    assert not found, found


def test_no_module_over_the_limit():
    long = {str(p.relative_to(ROOT)): n for p in _modules() if (n := len(p.read_text().splitlines())) > MODULE_LINES}
    assert not long, long


def _functions(tree: ast.Module):
    """Every function definition in ``tree``, nested ones included: a ``def`` is a statement, so only the statement
    lists (bodies, else and finally blocks, exception handlers, match cases) are searched, not every expression
    (``ast.walk`` visits all of them, about ten times the work)."""
    stack: list[ast.AST] = [tree]
    while stack:
        node = stack.pop()
        if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)):
            yield node
        for field in ("body", "orelse", "finalbody", "handlers", "cases"):
            stack.extend(getattr(node, field, None) or ())


def test_few_long_functions():
    long = []
    for p, tree in package_trees():
        for node in _functions(tree):
            n = node.end_lineno - node.lineno + 1
            if n > FUNCTION_LINES:
                long.append(f"{p.relative_to(ROOT)}:{node.name} ({n})")
    assert len(long) <= LONG_FUNCTIONS, long


def test_the_function_search_finds_what_a_full_walk_finds():
    """Nested, async, in classes, branches, handlers and match cases: the same definitions as ``ast.walk``."""
    source = """
def a():
    def b(): pass
class C:
    async def d(self): pass
    if x:
        def e(): pass
    else:
        def f(): pass
try:
    def g(): pass
except E:
    def h(): pass
finally:
    def i(): pass
for _ in y:
    def j(): pass
else:
    def k(): pass
with z:
    def m(): pass
match v:
    case 1:
        def n(): pass
f = lambda: (yield)
"""
    tree = ast.parse(source)
    walked = {n.name for n in ast.walk(tree) if isinstance(n, (ast.FunctionDef, ast.AsyncFunctionDef))}
    assert {n.name for n in _functions(tree)} == walked == set("abdefghijkmn")
