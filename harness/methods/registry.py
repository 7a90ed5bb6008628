"""The registered methods: the family modules (``FAMILIES``, listed here: a module of methods/
that is not listed is not read), each declaring its variants in a ``methods`` list; the registry
in its order (``METHODS``); the named groups, each derived from what a method is (its class,
order, roles: ``GROUPS``); and every way to ask for methods by name (``methods_named``,
``get_method``, ``parse_method``), by role (``with_role``) or for a case (``methods_for``,
``left_out``)."""
from __future__ import annotations

from contextlib import contextmanager
from dataclasses import replace

from ..core.names import assignments, look_up, split_spec
from ..core.plugins import is_external
from . import cones, mortar, nitsche, penalty
from .cones import BoundConstrained
from .external import EXTERNAL_PREFIX, External, read_external
from .method import DEGREES, PAPER, Method
from .plugins import MethodError, check_method, installed_methods, load_external
from .protocol import ContactLawMethod

# the family modules, each with its ``methods``
FAMILIES = (cones, nitsche, penalty, mortar)


def _place(m: Method) -> tuple:
    """The registry's order: the cones (the paper's P2 models first), then the weak methods,
    each by order; then the methods of degree k >= 3, by degree."""
    return (m.order > 2, m.order if m.order > 2 else 0, not isinstance(m, BoundConstrained), -m.order, m.name)


def _discover() -> dict[str, Method]:
    found = [check_method(m, f"harness/methods/{family.__name__.rsplit('.', 1)[-1]}.py (its `methods`)")
             for family in FAMILIES for m in family.methods]
    return {m.name: m for m in sorted(found, key=_place)}


METHODS = _discover()


def _of_kind(test) -> tuple[str, ...]:
    return tuple(name for name, m in METHODS.items() if test(m))


# Methods this process was given as objects (``known``): found by name like the registered ones.
_GIVEN: dict[str, Method] = {}


def with_role(role: str, methods=None) -> list[Method]:
    """Those of ``methods`` (default: the registered ones, in registry order) that declare
    ``role`` (``method.ROLES``: PAPER, BASELINE, REFERENCE, SWEPT, MESH_STUDY), in their order.
    Nothing outside ``methods/`` names a method: it asks for a role, which a method of your own
    may declare too (``Method.roles``)."""
    methods = METHODS.values() if methods is None else methods
    return [m for m in methods if isinstance(m, Method) and role in m.roles]


def role_names(role: str, methods=None) -> list[str]:
    """The names of ``with_role(role, methods)``."""
    return [m.name for m in with_role(role, methods)]


def names_with_role(role: str, names, methods=()) -> list[str]:
    """Those of ``names`` (method names: a results column, say) whose method declares ``role``,
    once each in their order: each looked up among ``methods`` (Method objects), then by name
    (``get_method``: the registered methods, those of ``known`` and the installed ones); a name
    this process does not know declares none."""
    given = {m.name: m for m in methods if isinstance(m, Method)}
    out = []
    for name in dict.fromkeys(names):
        try:
            method = given[name] if name in given else get_method(name)
        except ValueError:               # MethodError too: a method this process does not know
            continue
        if with_role(role, [method]):
            out.append(name)
    return out


@contextmanager
def known(methods):
    """Within the block, ``get_method`` and ``methods_named`` find each of ``methods`` (Method
    objects: a method of your own from a file, a module or Python) by its name, as the report's
    study finds the methods of its settings (which hold names)."""
    given = [m for m in methods if isinstance(m, Method) and METHODS.get(m.name) is not m]
    before = dict(_GIVEN)
    _GIVEN.update({m.name: m for m in given})
    try:
        yield
    finally:
        _GIVEN.clear()
        _GIVEN.update(before)


def method_choices() -> list[str]:
    return [*METHODS, *installed_methods(), *GROUPS, "all"]


def methods_named(names) -> list[Method]:
    """Methods by name, group ('paper' = mean + nodal) or 'all' (the package's own), in registry
    order, once each; then methods with parameters (``parse_method``), methods from files,
    modules and installed packages (``plugins``) and ``Method`` objects, in the order given."""
    names = [names] if isinstance(names, (str, Method)) else list(names)
    wanted, others = set(), []
    for name in names:
        if isinstance(name, Method):
            found = [check_method(name, "a method object")]
        elif name == "all":
            wanted |= set(METHODS)
            continue
        elif name in GROUPS:
            wanted |= set(GROUPS[name])
            continue
        elif name in METHODS:
            wanted.add(name)
            continue
        elif name in _GIVEN:
            found = [_GIVEN[name]]
        else:
            external = is_external(name) and name not in installed_methods()
            found = load_external(name) if external else [get_method(name)]
        others = _added(others, found)
    clash = [m.name for m in others if m.name in wanted and m is not METHODS.get(m.name)]
    if clash:
        raise MethodError(f"two methods named {clash[0]!r}: rename yours (the harness has one)")
    return [m for name, m in METHODS.items() if name in wanted] + others


def _added(others: list[Method], found: list[Method]) -> list[Method]:
    """``others`` and the methods of ``found`` not among them by name; an external method of a
    name already there (another case's folder of the same code and method, ``external:DIR`` given
    once per case) joins its solutions to that one's."""
    others = list(others)
    for method in found:
        same = next((i for i, o in enumerate(others) if o.name == method.name), None)
        if same is None:
            others.append(method)
        elif isinstance(method, External) and isinstance(others[same], External) and method != others[same]:
            others[same] = others[same].joined(method)
    return others


def methods_for(case, methods) -> list[Method]:
    """Those of ``methods`` that discretise ``case``'s physics, dimension and bodies (``Method.
    supports``), in the order given; a study runs each case with these, and says which it left
    out and why (``left_out``)."""
    return [m for m in methods if m.supports(case)]


def left_out(case, methods) -> list[tuple[str, str]]:
    """(name, why) of each of ``methods`` that does not discretise ``case`` (``Method.refusal``:
    its physics, dimension, bodies, or an order that needs an exact solution), in the order
    given: what ``methods_for`` leaves out, for a study to say in one line."""
    return [(m.name, reason) for m in methods for reason in [m.refusal(case)] if reason is not None]


def get_method(name: str) -> Method:
    """A registered method, one with parameters (``nitsche:gamma0=0.5,theta=-1``), or another
    code's solutions (``external:DIR``, ``external``)."""
    if name.startswith(EXTERNAL_PREFIX):
        return external(name[len(EXTERNAL_PREFIX):])
    if ":" in name:
        return parse_method(name)
    if name in METHODS:
        return METHODS[name]
    if name in _GIVEN:
        return _GIVEN[name]
    return look_up(installed_methods(), name, "method", MethodError, known=method_choices(),
                   also=", a file (path/to/method.py[:name]) or a module (package.module[:name])")


def external(folder, name: str | None = None) -> External:
    """Another code's solutions in ``folder`` as a method (``external.read_external``), expecting
    the rate of the harness method they discretise (the folder's ``like``), if it names one."""
    method = read_external(folder, name)
    return replace(method, expected=get_method(method.like).expected) if method.like else method


def parse_method(spec: str) -> Method:
    """``name:key=value,...``: the registered method ``name`` with those parameter values."""
    base, text = split_spec(spec)
    method = get_method(base)
    values = {}
    for key, value in assignments(text):
        try:
            values[key] = float(value)
        except (TypeError, ValueError):         # no "=" (None), or not a number
            raise ValueError(f"method parameters look like {base}:name=number,..., got {spec!r}") from None
    if not values:
        raise ValueError(f"no parameter values in {spec!r}")
    return method.with_parameters(**values)


# Named groups besides the method names themselves, each derived from what a method is, in
# registry order.
GROUPS = {
    PAPER: tuple(role_names(PAPER)),        # the methods that declare the role PAPER: mean, nodal
    # exact discrete inequalities in 2D (cones of nodal functionals, P1 and P2)
    "cones": _of_kind(lambda m: isinstance(m, BoundConstrained) and 2 in m.dimensions),
    # contact by a Gamma_C term (a contact law), P1 and P2
    "weak": _of_kind(lambda m: isinstance(m, ContactLawMethod) and m.order <= 2),
    "mortar": _of_kind(lambda m: 2 in m.bodies),                 # two bodies, non-matching meshes
    DEGREES: tuple(role_names(DEGREES)),    # the methods that declare the role DEGREES
    "high-order": _of_kind(lambda m: m.order > 2),              # k >= 3
}
