"""The examples gallery: each script in ``examples/`` is run when the
documentation builds, and its page shows the code, what it printed and the
figure it wrote.

``.. gallery-example:: name`` runs ``examples/name.py`` headless in a
fresh folder under the build's output; a script that fails, prints
nothing or writes no ``name.png`` is a build error.  Every example is
started when the build starts, all at once, so that they share the
machine's cores while Sphinx reads the other pages; a directive waits for
its own.
"""

import os
import pathlib
import shutil
import subprocess
import sys

from docutils import nodes
from docutils.parsers.rst import Directive
from sphinx.errors import ExtensionError

ROOT = pathlib.Path(__file__).resolve().parents[2]


#: timeout of one example, seconds
TIMEOUT = 900

#: name -> (process, folder) of the examples started and not yet shown
#: (kept here, not in Sphinx's environment, which is pickled)
_RUNS = {}


def _start(outdir, name):
    """Start ``examples/name.py`` headless in a fresh folder; ``(process,
    folder)``."""
    script = ROOT / 'examples' / f'{name}.py'
    work = pathlib.Path(outdir).parent / 'gallery' / name
    shutil.rmtree(work, ignore_errors=True)
    work.mkdir(parents=True)
    proc = subprocess.Popen(
        [sys.executable, str(script)], cwd=work, stdout=subprocess.PIPE,
        stderr=subprocess.PIPE, text=True,
        env={**os.environ, 'MPLBACKEND': 'Agg',
             'PYTHONPATH': str(ROOT) + os.pathsep +
             os.environ.get('PYTHONPATH', '')})
    return proc, work


def start_all(app):
    """Start every example before the pages are read."""
    for script in sorted((ROOT / 'examples').glob('*.py')):
        _RUNS[script.stem] = _start(app.outdir, script.stem)


class GalleryExample(Directive):
    required_arguments = 1

    def run(self):
        env = self.state.document.settings.env
        name = self.arguments[0]
        script = ROOT / 'examples' / f'{name}.py'
        proc, work = _RUNS.pop(name, None) or _start(env.app.outdir, name)
        try:
            stdout, stderr = proc.communicate(timeout=TIMEOUT)
        except subprocess.TimeoutExpired:
            proc.kill()
            proc.communicate()
            raise ExtensionError(f"example {name} ran over {TIMEOUT} s")
        figure = work / f'{name}.png'
        if proc.returncode or not stdout.strip() or not figure.exists():
            raise ExtensionError(f"example {name} failed "
                                 f"(exit {proc.returncode}): "
                                 f"{stderr[-2000:]}")
        # the figure goes where Sphinx copies images from
        images = pathlib.Path(env.srcdir) / '_gallery'
        images.mkdir(exist_ok=True)
        shutil.copy(figure, images / figure.name)
        env.note_dependency(str(script))
        code = nodes.literal_block(script.read_text(), script.read_text(),
                                   language='python')
        output = nodes.literal_block(stdout, stdout)
        image = nodes.image(uri=f'_gallery/{figure.name}',
                            alt=f'figure of {name}.py')
        para = nodes.paragraph(text='It prints:')
        return [image, code, para, output]


def stop_all(app, exception):
    """End the examples no page asked for."""
    while _RUNS:
        proc, _ = _RUNS.popitem()[1]
        proc.kill()
        proc.communicate()


def setup(app):
    app.add_directive('gallery-example', GalleryExample)
    app.connect('builder-inited', start_all)
    app.connect('build-finished', stop_all)
    return {'parallel_read_safe': True, 'version': '1'}
