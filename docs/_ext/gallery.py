"""The examples gallery: each script in ``examples/`` is run when the
documentation builds, and its page shows the code, what it printed and the
figure it wrote.

``.. gallery-example:: name`` runs ``examples/name.py`` headless in a
fresh folder under the build's output; a script that fails, prints
nothing or writes no ``name.png`` is a build error.
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


class GalleryExample(Directive):
    required_arguments = 1

    def run(self):
        env = self.state.document.settings.env
        name = self.arguments[0]
        script = ROOT / 'examples' / f'{name}.py'
        work = pathlib.Path(env.app.outdir).parent / 'gallery' / name
        shutil.rmtree(work, ignore_errors=True)
        work.mkdir(parents=True)
        proc = subprocess.run(
            [sys.executable, str(script)], cwd=work, capture_output=True,
            text=True, timeout=900,
            env={**os.environ, 'MPLBACKEND': 'Agg',
                 'PYTHONPATH': str(ROOT) + os.pathsep +
                 os.environ.get('PYTHONPATH', '')})
        figure = work / f'{name}.png'
        if proc.returncode or not proc.stdout.strip() or \
                not figure.exists():
            raise ExtensionError(f"example {name} failed "
                                 f"(exit {proc.returncode}): "
                                 f"{proc.stderr[-2000:]}")
        # the figure goes where Sphinx copies images from
        images = pathlib.Path(env.srcdir) / '_gallery'
        images.mkdir(exist_ok=True)
        shutil.copy(figure, images / figure.name)
        env.note_dependency(str(script))
        code = nodes.literal_block(script.read_text(), script.read_text(),
                                   language='python')
        output = nodes.literal_block(proc.stdout, proc.stdout)
        image = nodes.image(uri=f'_gallery/{figure.name}',
                            alt=f'figure of {name}.py')
        para = nodes.paragraph(text='It prints:')
        return [image, code, para, output]


def setup(app):
    app.add_directive('gallery-example', GalleryExample)
    return {'parallel_read_safe': True, 'version': '1'}
