"""The documentation builds with warnings as errors, and every public
function documents itself with a doctested example."""

import inspect
import re
import pathlib
import subprocess
import sys

import pytest

import controlext as cx

DOCS = pathlib.Path(__file__).parent.parent / 'docs'


def test_every_public_function_has_examples():
    missing = [name for name in cx.__all__
               if inspect.isfunction(getattr(cx, name)) and '>>>' not in
               (inspect.getdoc(getattr(cx, name)) or '')]
    assert not missing, missing


def test_every_public_name_is_in_the_api_reference():
    api = (DOCS / 'api.rst').read_text()
    missing = [name for name in cx.__all__ if f'   {name}\n' not in api]
    assert not missing, missing


@pytest.fixture(scope='module')
def built(tmp_path_factory):
    """The HTML documentation, built with warnings as errors (this runs
    every example script for the gallery and the closed-loop page's
    code)."""
    pytest.importorskip('sphinx')
    pytest.importorskip('numpydoc')
    out = tmp_path_factory.mktemp('docs')
    proc = subprocess.run(
        [sys.executable, '-m', 'sphinx', '-W', '--keep-going', '-b', 'html',
         '-q', '-d', str(out / 'doctrees'), str(DOCS), str(out / 'html')],
        capture_output=True, text=True, timeout=1200)
    assert proc.returncode == 0, proc.stderr
    return out / 'html'


@pytest.mark.slow
def test_sphinx_build_without_warnings(built):
    html = (built / 'generated' / 'controlext.coupled_observer.html') \
        .read_text()
    assert 'Examples' in html and 'Theorem 3.10' in html


@pytest.mark.slow
def test_closed_loop_page_has_its_figures(built):
    html = (built / 'closed_loop.html').read_text()
    figures = re.findall(r'<img[^>]+src="(_images/closed_loop[^"]+\.png)"',
                         html)
    assert len(figures) == 2, figures          # noisy run, LQR step
    for src in figures:
        assert (built / src).stat().st_size > 5000
    assert 'create_statefbk_iosystem' in html and 'ct.lqe' in html


@pytest.mark.slow
def test_gallery_shows_every_example_with_its_figure(built):
    html = (built / 'examples.html').read_text()
    for script in sorted((DOCS.parent / 'examples').glob('*.py')):
        src = f'_images/{script.stem}.png'
        assert src in html, script.stem
        assert (built / src).stat().st_size > 5000


@pytest.mark.slow
def test_math_needs_no_network_and_names_link_out(built):
    for page in ('guide.html', 'index.html'):
        html = (built / page).read_text()
        scripts = re.findall(r'<script[^>]+src="([^"]+)"', html)
        assert not [s for s in scripts if '://' in s], scripts
    assert (built / '_static' / 'mathjax' / 'tex-chtml.js').exists()
    # intersphinx: python-control's classes are links to its documentation
    index = (built / 'index.html').read_text()
    assert 'python-control.readthedocs.io/en/' in index and \
        'generated/control.StateSpace.html' in index


@pytest.mark.slow
def test_observer_page_shows_its_own_methods_first(built):
    html = (built / 'generated' / 'controlext.Observer.html').read_text()
    own = html.index('controlext.Observer.estimator')
    # python-control's inherited methods are not listed on the page
    assert 'controlext.Observer.bode_plot' not in html
    assert 'controlext.Observer.lft' not in html
    assert own > 0


@pytest.mark.slow
def test_tradeoff_page_has_its_figure(built):
    html = (built / 'tradeoffs.html').read_text()
    figures = re.findall(r'<img[^>]+src="(_images/tradeoffs[^"]+\.png)"',
                         html)
    # the transient figure (with the printed table) and the mixed front
    assert len(figures) == 2 and 'kalman' in html and 'h2hinfsyn' in html


@pytest.mark.slow
def test_no_glitches_in_the_built_pages(built):
    """What a newcomer saw in the built HTML: cross-reference targets
    printed literally, an extra that does not exist, a sentence rendered
    as a parameter; the MATLAB section without estim; no changelog."""
    pages = list(built.rglob('*.html'))
    assert len(pages) > 20
    for page in pages:
        html = page.read_text()
        for literal in ('python:None', 'python:list', 'python:tuple',
                        '[plot]'):
            assert literal not in html, (page.name, literal)
    hinf = (built / 'generated' / 'controlext.hinf_observer.html'
            ).read_text()
    params = hinf.split('Parameters')[1].split('Returns')[0]
    assert 'Every option is checked' not in params
    api = (built / 'api.html').read_text()
    assert 'controlext.matlab.estim' in api
    changes = (built / 'changelog.html').read_text()
    assert cx.__version__ in changes


@pytest.mark.slow
def test_printed_tables_do_not_wrap(built):
    """Printed tables are literal blocks: they scroll sideways rather than
    wrap, so their columns stay aligned at any window width."""
    css = (built / '_static' / 'wrap.css').read_text()
    assert 'white-space: pre;' in css and 'overflow-x: auto' in css
    assert 'pre-wrap' not in css
