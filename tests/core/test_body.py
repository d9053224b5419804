"""Bodies: validation, shapes against textbook formulas, inertia tensors, composites, presets."""

import math

import numpy as np
import pytest

import stability
from stability.free_body.model import axis_stability
from stability.core.body import PRESETS, Part, RigidBody


def _rotation(seed):
    """A random proper rotation (QR of a Gaussian matrix, signs fixed)."""
    rng = np.random.default_rng(seed)
    q, r = np.linalg.qr(rng.standard_normal((3, 3)))
    q = q * np.sign(np.diag(r))
    if np.linalg.det(q) < 0:
        q[:, 0] = -q[:, 0]
    return q


# ------------------------------------------------------------------------------ RigidBody


@pytest.mark.parametrize(
    "moments, match",
    [
        ((math.nan, 2.0, 3.0), "I1 must be finite"),
        ((1.0, math.inf, 3.0), "I2 must be finite"),
        ((1.0, 2.0, 0.0), r"I3 must be > 0 kg m\^2"),
        ((-1.0, 2.0, 3.0), r"I1 must be > 0 kg m\^2"),
        (("heavy", 2.0, 3.0), "I1 must be a number"),
        ((1.0, 2.0, 4.0), "violate the triangle inequality"),
    ],
)
def test_rigid_body_rejects_bad_moments(moments, match):
    with pytest.raises(ValueError, match=match):
        RigidBody(*moments)


def test_mathematical_body_and_exactly_flat_body_pass():
    assert RigidBody(1.0, 2.0, 4.0, physical=False).I3 == 4.0
    assert RigidBody(1.0, 2.0, 3.0).I3 == 3.0  # flat: I3 = I1 + I2 exactly


# --------------------------------------------------------------------------------- shapes


def test_box_ellipsoid_cylinder_match_textbook_formulas():
    m, a, b, c = 2.0, 0.3, 0.2, 0.1
    box = RigidBody.box(m, a, b, c)
    # I1 = m (b^2 + c^2) / 12 = 2 * 0.05 / 12, and cyclic.
    np.testing.assert_allclose(
        box.moments, [2 * 0.05 / 12, 2 * 0.10 / 12, 2 * 0.13 / 12], rtol=1e-15
    )
    ell = RigidBody.ellipsoid(m, a, b, c)
    # I1 = m (b^2 + c^2) / 5, and cyclic.
    np.testing.assert_allclose(ell.moments, [2 * 0.05 / 5, 2 * 0.10 / 5, 2 * 0.13 / 5], rtol=1e-15)
    cyl = RigidBody.cylinder(m, radius=0.1, length=0.6)
    # I1 = I2 = m (3 r^2 + l^2) / 12 = 2 * (0.03 + 0.36) / 12, I3 = m r^2 / 2 = 0.01.
    np.testing.assert_allclose(cyl.moments, [0.39 / 6, 0.39 / 6, 0.01], rtol=1e-15)
    assert cyl.I1 == cyl.I2
    sphere = RigidBody.ellipsoid(5.0, 0.2, 0.2, 0.2)
    np.testing.assert_allclose(sphere.moments, 0.4 * 5.0 * 0.04, rtol=1e-15)  # 2/5 m r^2


@pytest.mark.parametrize(
    "make, match",
    [
        (lambda: RigidBody.box(0.0, 1, 1, 1), "mass must be finite and > 0 in kg"),
        (lambda: RigidBody.box(-1.0, 1, 1, 1), "mass must be finite and > 0 in kg"),
        (lambda: RigidBody.box(1.0, 1, math.nan, 1), "b must be finite and > 0 in m"),
        (lambda: RigidBody.box(1.0, 1, 1, 0.0), "c must be finite and > 0 in m"),
        (lambda: RigidBody.ellipsoid(math.inf, 1, 1, 1), "mass must be finite and > 0"),
        (lambda: RigidBody.ellipsoid(1.0, -1, 1, 1), "a must be finite and > 0 in m"),
        (lambda: RigidBody.cylinder(1.0, 0.0, 1.0), "radius must be finite and > 0 in m"),
        (lambda: RigidBody.cylinder(1.0, 1.0, "long"), "length must be a number in m"),
    ],
)
def test_shape_constructors_reject_bad_dimensions(make, match):
    with pytest.raises(ValueError, match=match):
        make()


# ------------------------------------------------------------------------------ from_tensor


@pytest.mark.parametrize("seed", range(5))
def test_from_tensor_recovers_moments_and_axes_of_a_rotated_diagonal_tensor(seed):
    R = _rotation(seed)
    moments = np.array([0.7, 1.9, 2.2])
    J = R @ np.diag(moments) @ R.T
    body, axes = RigidBody.from_tensor(J)
    np.testing.assert_allclose(body.moments, moments, rtol=1e-14)
    assert np.linalg.det(axes) == pytest.approx(1.0, abs=1e-14)
    np.testing.assert_allclose(axes.T @ axes, np.eye(3), atol=1e-14)
    # Each principal axis is the matching column of R, up to sign.
    np.testing.assert_allclose(np.abs(np.sum(axes * R, axis=0)), 1.0, atol=1e-13)
    np.testing.assert_allclose(axes @ np.diag(body.moments) @ axes.T, J, atol=1e-14)


def test_from_tensor_sorts_and_keeps_a_proper_rotation():
    body, axes = RigidBody.from_tensor(np.diag([3.0, 1.0, 2.0]), name="sorted")
    assert body == RigidBody(1.0, 2.0, 3.0)
    assert body.name == "sorted"
    # Axis 1 (moment 1) is y, axis 2 (moment 2) is z, axis 3 is x: a cyclic, proper permutation.
    np.testing.assert_array_equal(axes, [[0, 0, 1], [1, 0, 0], [0, 1, 0]])


def test_from_tensor_accepts_a_flat_body_with_round_off():
    # A lamina: I3 = I1 + I2 exactly; rotated, the computed eigenvalues may break it by ulps
    # (by 2.9e-15 for seed 170, more than RigidBody's own 4-ulp slack): from_tensor clips that.
    for seed in range(200):
        R = _rotation(seed)
        body, _ = RigidBody.from_tensor(R @ np.diag([1.0, 2.0, 3.0]) @ R.T)
        assert body.I3 <= body.I1 + body.I2
        np.testing.assert_allclose(body.moments, [1.0, 2.0, 3.0], rtol=1e-14)


@pytest.mark.parametrize(
    "J, match",
    [
        (np.eye(2), r"J must have shape \(3, 3\)"),
        (np.ones(3), r"J must have shape \(3, 3\)"),
        ([[1, 0, 0], [0, math.nan, 0], [0, 0, 1]], "J must be finite"),
        ([["a", 0, 0], [0, 1, 0], [0, 0, 1]], "J must be real numbers in kg m\\^2, got strings"),
        (np.zeros((3, 3)), "all zeros"),
        ([[2, 0.1, 0], [-0.1, 2, 0], [0, 0, 3]], "not symmetric"),
        (np.diag([0.0, 1.0, 1.0]), "not positive definite"),  # a thin rod along x
        (np.diag([-1.0, 2.0, 3.0]), "not positive definite"),
        ([[1, 2, 0], [2, 1, 0], [0, 0, 1]], "not positive definite"),  # eigenvalues -1, 1, 3
        (np.diag([1.0, 1.0, 3.0]), "violate the triangle inequality"),
    ],
)
def test_from_tensor_rejects_bad_tensors(J, match):
    with pytest.raises(ValueError, match=match):
        RigidBody.from_tensor(J)


def test_from_tensor_mathematical_body():
    body, _ = RigidBody.from_tensor(np.diag([1.0, 1.0, 3.0]), physical=False)
    assert not body.physical and body.I3 == 3.0


# -------------------------------------------------------------------------------- composite


def test_composite_dumbbell_against_parallel_axis_by_hand():
    # Two solid spheres (m1 = 1 kg, m2 = 3 kg, r = 0.05 m) at x = -0.5 and x = +0.5 m on a rod
    # (M = 0.5 kg, radius 0.01 m, length 1 m) centred at the origin, along x.
    m1, m2, r, M, rr, length = 1.0, 3.0, 0.05, 0.5, 0.01, 1.0
    parts = [
        Part.ellipsoid(m1, r, r, r, position=(-0.5, 0, 0), name="left ball"),
        Part.ellipsoid(m2, r, r, r, position=(0.5, 0, 0), name="right ball"),
        Part.cylinder(M, rr, length, axis=(1, 0, 0), name="rod"),
    ]
    c = RigidBody.composite(parts, name="dumbbell")
    total = m1 + m2 + M
    x_c = (m1 * -0.5 + m2 * 0.5) / total  # = 1 / 4.5 m
    assert c.mass == total
    np.testing.assert_allclose(c.centre_of_mass, [x_c, 0, 0], atol=1e-16)
    # About the rod's axis: the balls' own 2/5 m r^2 and the rod's M rr^2 / 2; no offset.
    I_along = 0.4 * m1 * r**2 + 0.4 * m2 * r**2 + 0.5 * M * rr**2
    # Across: each part's own moment plus mass times its squared distance from x_c.
    I_across = (
        0.4 * m1 * r**2 + m1 * (-0.5 - x_c) ** 2
        + 0.4 * m2 * r**2 + m2 * (0.5 - x_c) ** 2
        + M * (3 * rr**2 + length**2) / 12 + M * x_c**2
    )
    np.testing.assert_allclose(c.body.moments, [I_along, I_across, I_across], rtol=1e-14)
    np.testing.assert_allclose(c.inertia, np.diag([I_along, I_across, I_across]), atol=1e-16)
    assert c.body.name == "dumbbell"
    assert axis_stability(c.body, 2) == "neutral"  # I2 = I3: no flip for a dumbbell


def test_composite_two_boxes_with_a_product_of_inertia_by_hand():
    # Box A: 1 kg, 0.2 x 0.1 x 0.1 m at the origin. Box B: 2 kg, 0.1 x 0.2 x 0.1 m at (0.3, 0.2, 0).
    parts = [
        Part.box(1.0, 0.2, 0.1, 0.1, name="A"),
        Part.box(2.0, 0.1, 0.2, 0.1, position=(0.3, 0.2, 0.0), name="B"),
    ]
    c = RigidBody.composite(parts)
    # Centre of mass (2 * 0.3, 2 * 0.2, 0) / 3 = (0.2, 2/15, 0); offsets dA, dB from it.
    np.testing.assert_allclose(c.centre_of_mass, [0.2, 2 / 15, 0.0], rtol=1e-15, atol=1e-17)
    dA, dB = (-0.2, -2 / 15), (0.1, 1 / 15)
    # Own moments (m (b^2 + c^2) / 12 ...) plus m (d_y^2 + d_z^2) etc.; J_xy = -sum m dx dy.
    Jxx = 1.0 * (0.01 + 0.01) / 12 + 2.0 * (0.04 + 0.01) / 12 + 1.0 * dA[1] ** 2 + 2.0 * dB[1] ** 2
    Jyy = 1.0 * (0.04 + 0.01) / 12 + 2.0 * (0.01 + 0.01) / 12 + 1.0 * dA[0] ** 2 + 2.0 * dB[0] ** 2
    Jzz = (1.0 * (0.04 + 0.01) / 12 + 2.0 * (0.01 + 0.04) / 12
           + 1.0 * (dA[0] ** 2 + dA[1] ** 2) + 2.0 * (dB[0] ** 2 + dB[1] ** 2))
    Jxy = -(1.0 * dA[0] * dA[1] + 2.0 * dB[0] * dB[1])
    assert (Jxx, Jyy, Jzz, Jxy) == pytest.approx((0.11 / 3, 0.0675, 0.119 / 1.2, -0.04), rel=1e-12)
    expected = np.array([[Jxx, Jxy, 0], [Jxy, Jyy, 0], [0, 0, Jzz]])
    np.testing.assert_allclose(c.inertia, expected, rtol=1e-14, atol=1e-17)
    # Principal moments of the xy block: mean -/+ sqrt(half-difference^2 + Jxy^2); then Jzz.
    mean, half = (Jxx + Jyy) / 2, math.hypot((Jxx - Jyy) / 2, Jxy)
    np.testing.assert_allclose(c.body.moments, [mean - half, mean + half, Jzz], rtol=1e-14)
    # The block's larger-moment axis (principal axis 2) lies at (1/2) atan2(2 Jxy, Jxx - Jyy)
    # from x in the xy plane; axis 3 is z.
    angle = 0.5 * math.atan2(2 * Jxy, Jxx - Jyy)
    direction = [math.cos(angle), math.sin(angle), 0.0]
    assert abs(c.axes[:, 1] @ direction) == pytest.approx(1.0, abs=1e-14)
    assert abs(c.axes[2, 2]) == pytest.approx(1.0, abs=1e-14)


def test_rotated_part_constructors_agree():
    R = _rotation(7)
    by_box = Part.box(1.5, 0.3, 0.2, 0.1, position=(1, 2, 3), rotation=R)
    by_body = Part.from_body(RigidBody.box(1.5, 0.3, 0.2, 0.1), 1.5, (1, 2, 3), rotation=R)
    np.testing.assert_allclose(by_box.inertia, by_body.inertia, rtol=1e-15)
    # A single rotated box: the composite finds the box's moments and axes again.
    c = RigidBody.composite([by_box])
    box = RigidBody.box(1.5, 0.3, 0.2, 0.1)
    np.testing.assert_allclose(c.body.moments, box.moments, rtol=1e-14)
    np.testing.assert_allclose(np.abs(np.sum(c.axes * R, axis=0)), 1.0, atol=1e-13)
    np.testing.assert_allclose(c.centre_of_mass, [1, 2, 3])
    # A cylinder along x = a cylinder body whose axis 3 is turned onto x.
    to_x = np.array([[0.0, 0.0, 1.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]])  # columns: y, z, x
    along_x = Part.cylinder(2.0, 0.1, 0.5, axis=(3.0, 0, 0))
    turned = Part.from_body(RigidBody.cylinder(2.0, 0.1, 0.5), 2.0, (0, 0, 0), rotation=to_x)
    np.testing.assert_allclose(along_x.inertia, turned.inertia, rtol=1e-15)


def test_part_is_immutable():
    part = Part.box(1.0, 0.1, 0.2, 0.3)
    with pytest.raises(ValueError):
        part.inertia[0, 0] = 5.0  # read-only array
    with pytest.raises(AttributeError):
        part.mass = 2.0


@pytest.mark.parametrize(
    "make, match",
    [
        (lambda: RigidBody.composite([]), "non-empty list of stability.Part"),
        (lambda: RigidBody.composite(None), "non-empty list of stability.Part"),
        (lambda: RigidBody.composite([Part.point(1.0, (0, 0, 0)), 3.0]), r"parts\[1\] must be"),
        (lambda: RigidBody.composite([Part.point(1.0, (0, 0, 0)), Part.point(1.0, (1, 0, 0))]),
         "not positive definite"),  # two point masses: a line, no moment about it
        (lambda: Part.point(0.0, (0, 0, 0)), "mass of part 'point' must be finite and > 0"),
        (lambda: Part.point(1.0, (0, 0)), r"position of part 'point' must have shape \(3,\)"),
        (lambda: Part.point(1.0, (0, math.nan, 0)), "position of part 'point' must be finite"),
        (lambda: Part(1.0, np.diag([1.0, -2.0, 1.0]), (0, 0, 0)), "negative principal moment"),
        (lambda: Part(1.0, [[1, 0.5, 0], [0, 1, 0], [0, 0, 1]], (0, 0, 0)), "not symmetric"),
        (lambda: Part(1.0, np.eye(2), (0, 0, 0)), r"must have shape \(3, 3\)"),
        (lambda: Part.box(1.0, 1, 1, 1, rotation=2 * np.eye(3)), "rotation must be orthogonal"),
        (lambda: Part.cylinder(1.0, 1, 1, axis=(0, 0, 0)), "must be a non-zero vector"),
        (lambda: Part.from_body((1, 2, 3), 1.0, (0, 0, 0)), "body must be a stability.RigidBody"),
    ],
)
def test_composite_and_parts_reject_bad_input(make, match):
    with pytest.raises(ValueError, match=match):
        make()


# ---------------------------------------------------------------------------------- presets


@pytest.mark.parametrize("name", sorted(PRESETS))
def test_every_preset_has_a_clearly_intermediate_axis_2(name):
    body = RigidBody.preset(name)
    assert body.name == name
    I1, I2, I3 = body.moments
    assert I1 < I2 < I3
    assert min(I2 - I1, I3 - I2) >= 0.08 * (I3 - I1)
    assert [axis_stability(body, a) for a in (1, 2, 3)] == ["stable", "unstable", "stable"]
    assert name in RigidBody.presets() and RigidBody.presets()[name] == PRESETS[name].description


def test_tennis_racket_preset_is_a_realistic_racket():
    c = RigidBody.composite(PRESETS["tennis_racket"].parts())
    assert c.mass == pytest.approx(0.302)
    # Balance point: grip 0.110 kg at 0.095 m, throat 0.035 kg at 0.275 m, head 0.157 kg at 0.525 m.
    balance = (0.110 * 0.095 + 0.035 * 0.275 + 0.157 * 0.525) / 0.302
    assert c.centre_of_mass[0] == pytest.approx(balance, rel=1e-12)
    np.testing.assert_allclose(c.centre_of_mass[1:], 0.0, atol=1e-15)
    np.testing.assert_allclose(np.abs(c.axes), np.eye(3), atol=1e-12)  # principal = x, y, z
    swingweight = c.body.I2 + c.mass * (c.centre_of_mass[0] - 0.10) ** 2  # about y at 10 cm
    assert 0.028 < swingweight < 0.035  # kg m^2, makers publish ~0.030-0.033
    assert 0.0012 < c.body.I1 < 0.0016  # twistweight, kg m^2, ~13-15 kg cm^2 published
    # Nearly flat: I3 - (I1 + I2) is only the grip's and frame's depth.
    assert 0.0 < c.body.I1 + c.body.I2 - c.body.I3 < 0.01 * c.body.I3


def test_phone_preset_is_the_box():
    phone = RigidBody.preset("phone")
    np.testing.assert_allclose(phone.moments, RigidBody.box(0.17, 0.147, 0.0715, 0.0078).moments,
                               rtol=1e-14)


@pytest.mark.parametrize("name", ["racket", "", None, "Tennis_Racket"])
def test_unknown_preset_lists_the_known_ones(name):
    with pytest.raises(ValueError, match="unknown preset .*known presets: book, phone, t_handle, "
                                         "tennis_racket"):
        RigidBody.preset(name)


def test_part_is_exported():
    assert stability.Part is Part


@pytest.mark.parametrize("moments", [(1.0, 2.0, 3.0), (3.0, 1.0, 2.5), (1.0, 1.0, 2.0),
                                     (2.0, 2.0, 2.0)])
def test_a_body_describes_its_axes_as_the_linear_theory_does(moments):
    """axis_summary / describe / _repr_html_: Omega^2 at unit spin is analytic.omega_squared's,
    the word is axis_stability's, and the unstable axis's growth rate is growth_rate's."""
    from stability.free_body.model import axis_stability, growth_rate, omega_squared

    body = stability.RigidBody(*moments, physical=False)
    rows = body.axis_summary()
    for row in rows:
        assert row["omega_squared"] == pytest.approx(float(omega_squared(body, row["axis"], 1.0)),
                                                     rel=1e-15, abs=0.0)
        assert row["stability"] == str(axis_stability(body, row["axis"]))
        if row["stability"] == "unstable":
            assert f"exp({float(growth_rate(body, row['axis'], 1.0)):.4g} W t)" in row[
                "departure"]
    assert [r["rank"] for r in rows].count("intermediate") == (len(set(moments)) == 3)
    text = body.describe()
    assert text.splitlines()[0] == repr(body) and len(text.splitlines()) == 5
    html = body._repr_html_()
    assert html.count("<tr>") == 4 and "kg m²" in html
