"""Sphinx configuration for controlext."""

import os
import sys

sys.path.insert(0, os.path.abspath('..'))
os.environ.setdefault('MPLBACKEND', 'Agg')

project = 'controlext'
author = 'controlext developers'
copyright = '2026, controlext developers'
import controlext  # noqa: E402

release = controlext.__version__

extensions = [
    'sphinx.ext.autodoc',
    'sphinx.ext.autosummary',
    'sphinx.ext.mathjax',
    'numpydoc',
]
autosummary_generate = True
autodoc_default_options = {'members': True, 'inherited-members': False}
numpydoc_show_class_members = False
numpydoc_class_members_toctree = False
exclude_patterns = ['_build', 'generated/*.rst~']
html_theme = 'alabaster'
html_static_path = []
suppress_warnings = ['toc.excluded']
