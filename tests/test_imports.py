"""The package's import graph has no circle, counting imports inside
functions (which would otherwise hide one) and leaving out those made for
type checking only."""

import ast
import pathlib

import controlext

ROOT = pathlib.Path(controlext.__file__).parent


def _module(path):
    rel = path.relative_to(ROOT.parent).with_suffix('')
    parts = list(rel.parts)
    if parts[-1] == '__init__':
        parts = parts[:-1]
    return '.'.join(parts)


def _imports(path):
    """The package modules ``path`` imports, outside TYPE_CHECKING."""
    tree = ast.parse(path.read_text())
    skip = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.If) and 'TYPE_CHECKING' in ast.unparse(
                node.test):
            skip.update(id(n) for n in ast.walk(node))
    name = _module(path)
    package = name if path.name == '__init__.py' else name.rpartition('.')[0]
    found = set()
    for node in ast.walk(tree):
        if id(node) in skip or not isinstance(node, ast.ImportFrom):
            continue
        if node.level:
            base = package.split('.')
            base = base[:len(base) - node.level + 1]
            target = '.'.join(base + ([node.module] if node.module else []))
        else:
            target = node.module or ''
        if not target.startswith('controlext'):
            continue
        for alias in node.names:
            sub = f'{target}.{alias.name}'
            found.add(sub if (ROOT.parent / (sub.replace('.', '/') + '.py')
                              ).exists() else target)
    return found


def graph():
    """``{module: imported package modules}`` (packages resolved to their
    ``__init__``)."""
    return {_module(p): _imports(p) for p in ROOT.rglob('*.py')}


def circles(edges):
    """Every module that lies on a circle, with one circle through it."""
    found = {}
    for start in edges:
        stack = [(start, [start])]
        seen = set()
        while stack:
            node, path = stack.pop()
            for nxt in edges.get(node, ()):
                if nxt == start:
                    found.setdefault(start, path + [start])
                elif nxt not in seen:
                    seen.add(nxt)
                    stack.append((nxt, path + [nxt]))
    return found


def test_no_import_circles():
    edges = graph()
    # a package's __init__ re-exports its modules: an import of the
    # package from inside it is one of a module, not a circle
    for name in list(edges):
        edges[name] = {t for t in edges[name]
                       if not (name.startswith(t + '.') and
                               t in ('controlext', 'controlext.synthesis',
                                     'controlext.paper'))}
    found = circles(edges)
    assert not found, '\n'.join(' -> '.join(c) for c in found.values())
