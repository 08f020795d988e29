"""Every parameter of the public API is documented (numpydoc's
Parameters section; for a dataclass, Parameters or Attributes), as
python-control checks of its own functions."""

import dataclasses
import inspect

import pytest
from numpydoc.docscrape import ClassDoc, FunctionDoc

import controlext as cx
import controlext.matlab as cm


def _public():
    for module, names in ((cx, cx.__all__), (cm, ['estim', 'obsim'])):
        for name in names:
            obj = getattr(module, name)
            if inspect.isclass(obj) and issubclass(obj, (Exception,
                                                         Warning)):
                continue            # the exceptions take a message
            if inspect.isclass(obj) or inspect.isfunction(obj):
                yield f'{module.__name__}.{name}', obj


def _documented(obj):
    doc = ClassDoc(obj) if inspect.isclass(obj) else FunctionDoc(obj)
    sections = ['Parameters', 'Other Parameters']
    if dataclasses.is_dataclass(obj):
        sections.append('Attributes')
    names = set()
    for section in sections:
        for param in doc[section]:
            names.update(n.strip().lstrip('*') for n in param.name.split(','))
    return names


@pytest.mark.parametrize('name, obj', list(_public()),
                         ids=[name for name, _ in _public()])
def test_every_parameter_is_documented(name, obj):
    params = [p for p in inspect.signature(obj).parameters if p != 'self']
    missing = [p for p in params if p not in _documented(obj)]
    assert not missing, f"{name}: undocumented {missing}"
