"""Intersphinx without a network: inventories written from the installed
packages.

Sphinx's intersphinx reads each project's ``objects.inv`` from its
documentation site; the documentation builds offline, so this extension
writes one inventory per project from the names the installed package
exports, with the address pattern of that project's documentation (the
links in the built pages point at the public documentation, as with a
downloaded inventory).
"""

import importlib
import inspect
import pathlib
import zlib

#: project -> (documentation root, [(module, page pattern)])
PROJECTS = {
    'control': ('https://python-control.readthedocs.io/en/{version}/',
                [('control', 'generated/{name}.html')]),
    'numpy': ('https://numpy.org/doc/stable/',
              [('numpy', 'reference/generated/{name}.html'),
               ('numpy.linalg', 'reference/generated/{name}.html')]),
    'scipy': ('https://docs.scipy.org/doc/scipy/',
              [('scipy.linalg', 'reference/generated/{name}.html'),
               ('scipy.optimize', 'reference/generated/{name}.html')]),
}
#: a few standard-library names the API pages use
PYTHON = ('https://docs.python.org/3/', [
    ('concurrent.futures.Executor', 'py:class',
     'library/concurrent.futures.html#concurrent.futures.Executor'),
    ('dict', 'py:class', 'library/stdtypes.html#dict'),
    ('float', 'py:class', 'library/functions.html#float'),
    ('int', 'py:class', 'library/functions.html#int'),
    ('str', 'py:class', 'library/stdtypes.html#str'),
    ('bool', 'py:class', 'library/functions.html#bool'),
    ('list', 'py:class', 'library/stdtypes.html#list'),
    ('tuple', 'py:class', 'library/stdtypes.html#tuple'),
    ('object', 'py:class', 'library/functions.html#object'),
    ('None', 'py:data', 'library/constants.html#None'),
    ('True', 'py:data', 'library/constants.html#True'),
    ('False', 'py:data', 'library/constants.html#False'),
    # what numpydoc's type aliases refer to
    ('sequence', 'std:term', 'glossary.html#term-sequence'),
    ('bltin-boolean-values', 'std:label',
     'library/stdtypes.html#boolean-type-bool'),
])
#: NumPy glossary terms numpydoc's aliases refer to
NUMPY_TERMS = [('array_like', 'std:term', 'glossary.html#term-array_like'),
               ('array', 'std:term', 'glossary.html#term-array')]


def _entries(module_name, pattern):
    module = importlib.import_module(module_name)
    names = getattr(module, '__all__', None) or [
        n for n in dir(module) if not n.startswith('_')]
    for name in sorted(set(names)):
        obj = getattr(module, name, None)
        if obj is None:
            continue
        full = f'{module_name}.{name}'
        role = 'py:class' if inspect.isclass(obj) else 'py:function' \
            if callable(obj) else None
        if role is None:
            continue
        yield full, role, pattern.format(name=full)
        if role == 'py:class':
            for attr, value in vars(obj).items():
                if not attr.startswith('_') and callable(value):
                    yield (f'{full}.{attr}', 'py:method',
                           pattern.format(name=full) + f'#{full}.{attr}')


def write_inventory(path, project, version, entries):
    """An ``objects.inv`` (format 2) with ``entries`` (name, role, uri)."""
    head = (f"# Sphinx inventory version 2\n# Project: {project}\n"
            f"# Version: {version}\n"
            "# The remainder of this file is compressed using zlib.\n")
    body = ''.join(f"{name} {role} 1 {uri} -\n"
                   for name, role, uri in entries)
    path.write_bytes(head.encode() + zlib.compress(body.encode()))


def mapping(folder):
    """The ``intersphinx_mapping`` of local inventories under ``folder``."""
    folder = pathlib.Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    out = {}
    for project, (root, modules) in PROJECTS.items():
        version = importlib.import_module(project).__version__
        entries = [e for module, pattern in modules
                   for e in _entries(module, pattern)]
        if project == 'numpy':
            entries += NUMPY_TERMS
        path = folder / f'{project}.inv'
        write_inventory(path, project, version, entries)
        out[project] = (root.format(version=version), str(path))
    path = folder / 'python.inv'
    write_inventory(path, 'Python', '3', PYTHON[1])
    out['python'] = (PYTHON[0], str(path))
    return out
