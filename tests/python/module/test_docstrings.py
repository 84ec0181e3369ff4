"""Every public callable of the Python module `icobrdf` documents itself in numpy-doc form (python/bindings.hpp),
so that the rule cannot rot: each function and method has a docstring with a "Parameters" or "Returns"
section, each class one with "Parameters" or "Attributes", and each property a docstring."""
import inspect

import pytest

import icobrdf

# numpy-doc section headings: the title, then a line of dashes as long as it.
SECTIONS = ("Parameters", "Returns", "Attributes")


def has_section(doc, names):
    lines = (doc or "").splitlines()
    return any(lines[k].strip() in names and lines[k + 1].strip() == "-" * len(lines[k].strip()) for k in range(len(lines) - 1))


def public(obj):
    return [(name, getattr(obj, name)) for name in dir(obj) if not name.startswith("_")]


def module_functions():
    return [(name, f) for name, f in public(icobrdf) if callable(f) and not inspect.isclass(f)]


def classes():
    return [(name, c) for name, c in public(icobrdf) if inspect.isclass(c)]


def methods():
    out = []
    for cname, c in classes():
        for name in dir(c):
            if name.startswith("_"):
                continue
            attr = inspect.getattr_static(c, name)
            if isinstance(attr, property):
                continue
            member = getattr(c, name)
            if callable(member):
                out.append((f"{cname}.{name}", member))
    return out


def properties():
    out = []
    for cname, c in classes():
        for name in dir(c):
            if not name.startswith("_") and isinstance(inspect.getattr_static(c, name), property):
                out.append((f"{cname}.{name}", inspect.getattr_static(c, name)))
    return out


def test_the_module_has_public_callables_to_check():
    # The lists below must not be empty by accident (an import of the wrong module, a renamed attribute).
    assert len(module_functions()) >= 10
    assert len(classes()) >= 5
    assert len(methods()) >= 5
    assert len(properties()) >= 10


@pytest.mark.parametrize("name,f", module_functions() + methods())
def test_functions_have_parameters_or_returns(name, f):
    assert has_section(f.__doc__, ("Parameters", "Returns")), f"{name}: no numpy-doc Parameters or Returns section in {f.__doc__!r}"


@pytest.mark.parametrize("name,c", classes())
def test_classes_have_parameters_or_attributes(name, c):
    assert has_section(c.__doc__, ("Parameters", "Attributes")), f"{name}: no numpy-doc Parameters or Attributes section in {c.__doc__!r}"


@pytest.mark.parametrize("name,p", properties())
def test_properties_have_a_docstring(name, p):
    assert (p.__doc__ or "").strip(), f"{name}: no docstring"


def test_the_check_fails_on_a_one_line_docstring():
    # The check itself: a summary line alone, or a heading without its dashes, is not a section.
    assert not has_section("Values of every mode at n pairs: n x modes", SECTIONS)
    assert not has_section("Summary.\n\nParameters\n\norder : int", SECTIONS)
    assert has_section("Summary.\n\nParameters\n----------\norder : int", SECTIONS)
