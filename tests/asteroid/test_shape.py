"""Mass properties of shape meshes against exact moments; bad shape models refused in one line."""

import math

import numpy as np
import pytest

from stability.asteroid.lightcurve import ellipsoid_mesh
from stability.asteroid.shape import mass_properties

trimesh = pytest.importorskip("trimesh")

#: An L-shaped (non-convex) outline in the x-y plane, counter-clockwise, and its split into
#: two rectangles (x0, x1, y0, y1) for the exact moments.
L_OUTLINE = [(0, 0), (3, 0), (3, 1), (1, 1), (1, 2.5), (0, 2.5)]
L_PARTS = [(0, 3, 0, 1), (0, 1, 1, 2.5)]
L_CAP = [(0, 1, 2), (0, 2, 3), (0, 3, 4), (0, 4, 5)]  # a fan inside the L


def prism(outline, cap, height):
    """Closed mesh of a prism over a polygon, z in [0, height], outward facets."""
    n = len(outline)
    v = np.array([(x, y, 0.0) for x, y in outline] + [(x, y, height) for x, y in outline])
    faces = [(a, c, b) for a, b, c in cap] + [(a + n, b + n, c + n) for a, b, c in cap]
    for i in range(n):
        j = (i + 1) % n
        faces += [(i, j, j + n), (i, j + n, i + n)]
    return v, np.array(faces)


def box_tensor(x0, x1, y0, y1, z0, z1, rho):
    """Inertia tensor of a box about the origin, and its mass and centroid."""
    m = rho * (x1 - x0) * (y1 - y0) * (z1 - z0)
    c = np.array([x0 + x1, y0 + y1, z0 + z1]) / 2
    d = np.array([x1 - x0, y1 - y0, z1 - z0])
    J = m / 12 * np.diag([d[1]**2 + d[2]**2, d[0]**2 + d[2]**2, d[0]**2 + d[1]**2])
    return J + m * (c @ c * np.eye(3) - np.outer(c, c)), m, c


def test_cube_moments_are_exact():
    box = trimesh.creation.box(extents=(2.0, 2.0, 2.0))
    p = mass_properties((box.vertices, box.faces), density=3.0)
    exact = 3.0 * 8.0 * (4.0 + 4.0) / 12.0
    assert p.mass == pytest.approx(24.0, rel=1e-14)
    assert np.abs(p.moments / exact - 1.0).max() < 1e-12


def test_l_shaped_solid_matches_its_two_boxes_to_round_off():
    h, rho = 0.7, 2.5
    p = mass_properties(prism(L_OUTLINE, L_CAP, h), density=rho)
    parts = [box_tensor(x0, x1, y0, y1, 0.0, h, rho) for x0, x1, y0, y1 in L_PARTS]
    mass = sum(m for _, m, _ in parts)
    com = sum(m * c for _, m, c in parts) / mass
    J = sum(j for j, _, _ in parts) - mass * (com @ com * np.eye(3) - np.outer(com, com))
    assert abs(p.mass / mass - 1.0) < 1e-12
    assert np.abs(p.center_of_mass - com).max() < 1e-12
    assert np.abs(p.inertia - J).max() < 1e-12 * np.abs(J).max()
    exact = np.linalg.eigvalsh(J)
    assert np.abs(p.moments / exact - 1.0).max() < 1e-12
    assert np.allclose(p.axes @ np.diag(p.moments) @ p.axes.T, p.inertia, atol=1e-12)
    assert p.body().moments.tolist() == p.moments.tolist()


@pytest.mark.parametrize("rings", [32, 64])
def test_meshed_ellipsoid_matches_its_moments_to_the_mesh_resolution(rings):
    """The mesh is the affine image of a latitude-longitude sphere mesh whose cells span
    delta = pi / rings: its facets lie within cos(delta / sqrt 2) of the centre, so the solid
    holds the ellipsoid scaled by lambda = cos(delta / sqrt 2) and lies inside it, and each
    moment is within 1 - lambda^5 of the exact one (below); it falls as rings^-2."""
    a, b, c = 3.0, 2.0, 1.0
    exact = 4 / 3 * math.pi * a * b * c / 5 * np.array([b*b + c*c, a*a + c*c, a*a + b*b])
    tol = 1.0 - math.cos(math.pi / rings / math.sqrt(2.0)) ** 5
    p = mass_properties(ellipsoid_mesh(a, b, c, rings))
    err = np.abs(p.moments / np.sort(exact) - 1.0)
    assert np.all(p.moments < np.sort(exact)) and err.max() < tol
    coarse = mass_properties(ellipsoid_mesh(a, b, c, rings // 2))
    ratio = np.abs(coarse.moments / np.sort(exact) - 1.0) / err
    assert np.all(np.abs(ratio - 4.0) < 0.1)  # second order in the resolution
    assert np.allclose(np.abs(p.axes), np.eye(3), atol=1e-12)


def test_stl_and_obj_files_read_as_the_same_solid(tmp_path):
    v, f = prism(L_OUTLINE, L_CAP, 1.0)
    mesh = trimesh.Trimesh(v, f)
    arrays = mass_properties((v, f))
    for kind in ("stl", "obj"):
        mesh.export(tmp_path / f"l.{kind}")
        p = mass_properties(tmp_path / f"l.{kind}")
        assert p.volume == pytest.approx(3.0 * 1.0 + 1.0 * 1.5, rel=1e-6)  # float32 in STL
        assert np.allclose(p.moments, arrays.moments, rtol=1e-6)


def one_line(call):
    with pytest.raises(ValueError) as info:
        call()
    message = str(info.value)
    assert "\n" not in message, message
    return message


def test_bad_shape_models_are_refused_in_one_line(tmp_path):
    v, f = prism(L_OUTLINE, L_CAP, 1.0)
    assert "not watertight" in one_line(lambda: mass_properties((v, f[:-1])))
    assert "facets face inwards" in one_line(lambda: mass_properties((v, f[:, ::-1])))
    assert "no such file" in one_line(lambda: mass_properties(tmp_path / "none.stl"))
    (tmp_path / "x.pkl").write_bytes(b"\x80\x04")
    assert "must be one of obj, stl" in one_line(lambda: mass_properties(tmp_path / "x.pkl"))
    (tmp_path / "bad.stl").write_bytes(b"\x00" * 40)
    assert "bad.stl" in one_line(lambda: mass_properties(tmp_path / "bad.stl"))
