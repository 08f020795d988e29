"""Sphinx configuration for controlext."""

import os
import sys

sys.path.insert(0, os.path.abspath('..'))
sys.path.insert(0, os.path.abspath('_ext'))
os.environ.setdefault('MPLBACKEND', 'Agg')

project = 'controlext'
author = 'controlext developers'
copyright = '2026, controlext developers'
import controlext  # noqa: E402

release = controlext.__version__

import inventories  # noqa: E402

extensions = [
    'sphinx.ext.autodoc',
    'sphinx.ext.autosummary',
    'sphinx.ext.intersphinx',
    'sphinx.ext.mathjax',
    'sphinx-mathjax-offline',       # MathJax served from _static, no CDN
    'matplotlib.sphinxext.plot_directive',
    'numpydoc',
    'gallery',
]
# links to python-control, NumPy, SciPy and Python from inventories
# written from the installed packages (the build needs no network)
intersphinx_mapping = inventories.mapping(
    os.path.join(os.path.dirname(__file__), '_build', 'inventories'))
intersphinx_disabled_reftypes = []
# the API pages: each class's own members first, in source order; the
# signatures without their type hints (the parameter lists say the types)
autodoc_member_order = 'bysource'
autodoc_typehints = 'none'
# figures of the closed-loop page are computed at build time
plot_include_source = True
plot_html_show_source_link = False
plot_html_show_formats = False
plot_formats = [('png', 80)]
autosummary_generate = True
autodoc_default_options = {'members': True, 'inherited-members': False}
numpydoc_show_class_members = False
# parameter types link to their documentation (control.StateSpace, ...)
numpydoc_xref_param_type = True
numpydoc_xref_aliases = {
    'StateSpace': 'control.StateSpace',
    'TimeResponseData': 'control.TimeResponseData',
    'ndarray': 'numpy.ndarray',
    'Executor': 'concurrent.futures.Executor',
}
numpydoc_xref_ignore = {'optional', 'or', 'of', 'default', 'array_like',
                        'callable', 'sequence', 'scalar', 'shape', 'None'}
numpydoc_class_members_toctree = False
exclude_patterns = ['_build', 'generated/*.rst~', '_gallery']
html_theme = 'alabaster'
html_theme_options = {'page_width': '1100px'}
# code blocks wrap instead of overflowing the page
html_css_files = ['wrap.css']
html_static_path = ['_static']
suppress_warnings = ['toc.excluded']
