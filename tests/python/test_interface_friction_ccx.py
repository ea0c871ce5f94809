"""Friction in a contact pair (issue 19), solved by CalculiX: the two stacked steel plates of
test_interface_kinds_ccx (200 x 20 x 5 mm, clamped at x = 0, 100 N pressing down on the top
face) with a Coulomb friction coefficient between them, and a squeeze of 1 N/mm^2 on both
outer faces that presses them together without bending them.

Theory: friction can only hinder the plates' slip along each other, so the tip deflection
lies between bonded (one 10 mm beam, Euler-Bernoulli 0.2857 mm) and frictionless contact
(two 5 mm beams, 4x that), and it falls as the friction coefficient rises. The bonded beam
needs a shear flow of V Q / I = 0.15 V at the interface, at most 15 N/mm at the clamp;
friction offers mu x (20 N/mm of squeeze + about 0.25 N/mm of the load): with mu = 1 that
is more than enough everywhere, so the plates stick and bend nearly as one beam (the stick
slope lets them shift a little elastically, see src/README.md); with mu = 0.1 (2 N/mm) most
of the length slips, and the deflection follows from the slip: friction c per length acts on
both plates 2.5 mm from their axes, a couple 5 c s (s = L - x) the plates' bending need not
carry, M = q s^2 / 2 - 5 c s, so by the unit load method
    deflection = (q L^4 / 8 - 5 c L^3 / 3) / (2 E I_5),   I_5 = 20 x 5^3 / 12."""
import os

import pytest

from test_interface_kinds_ccx import EULER_BERNOULLI, solve
from test_writers_meshio import require_programs

SQUEEZE = 1.0  # N/mm^2
LOAD, LENGTH, WIDTH, E = 0.5, 200.0, 20.0, 210000.0  # q in N/mm (100 N over 200 mm), mm, N/mm^2


def slipping_deflection(mu):
    """Tip deflection of the plates slipping all along with friction mu (module docstring):
    the normal force per length is the squeeze plus the half of the load the contact passes."""
    c = mu * (SQUEEZE * WIDTH + LOAD / 2)
    return (LOAD * LENGTH ** 4 / 8 - 5 * c * LENGTH ** 3 / 3) / (2 * E * WIDTH * 5.0 ** 3 / 12)


@pytest.fixture(scope="module")
def tip_deflection(tmp_path_factory):
    require_programs({"ccx": "calculix-ccx"})
    folder = str(tmp_path_factory.mktemp("interface_friction"))
    result = {}
    for mu in (0.1, 0.3, 1.0):
        mesh, uz, _ = solve(os.path.join(folder, "mu%g" % mu), {"kind": "contact", "friction": mu}, "down",
                            squeeze=SQUEEZE)
        assert mesh.report["interfaces"][0]["friction"] == mu
        result[mu] = -uz.mean()
    print("tip deflection by friction coefficient: %s (bonded theory %.4f, frictionless 4x = %.4f mm)"
          % (", ".join("mu %g: %.4f" % kv for kv in result.items()), EULER_BERNOULLI, 4 * EULER_BERNOULLI))
    return result


def test_friction_deflection_lies_between_bonded_and_frictionless(tip_deflection):
    for mu, deflection in tip_deflection.items():
        assert 0.97 * EULER_BERNOULLI < deflection < 0.97 * 4 * EULER_BERNOULLI, mu


def test_more_friction_deflects_less(tip_deflection):
    assert tip_deflection[0.3] < 0.95 * tip_deflection[0.1]
    assert tip_deflection[1.0] < 0.95 * tip_deflection[0.3]


def test_slipping_plates_deflect_as_the_friction_couple_says(tip_deflection):
    # mu = 0.1: 2 N/mm, far below the 15 N/mm that sticking would need over most of the length.
    print("mu 0.1: %.4f mm, theory for slip all along %.4f mm" % (tip_deflection[0.1], slipping_deflection(0.1)))
    assert tip_deflection[0.1] == pytest.approx(slipping_deflection(0.1), rel=0.05)


def test_plates_that_stick_bend_nearly_as_one_beam(tip_deflection):
    # mu = 1 holds everywhere; the elastic stick (slope 1/100 of the normal one) adds a little.
    assert tip_deflection[1.0] < 1.05 * EULER_BERNOULLI
