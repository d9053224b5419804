"""Mass properties of a shape model: a closed triangle mesh (OBJ, STL, PLY, OFF) of uniform
density -> volume, mass, centre of mass, inertia tensor, principal moments and axes, a RigidBody.

The integrals are those of the divergence theorem over the facets, exact for a polyhedron
(Mirtich, J. Graphics Tools 1, 31 (1996); Eberly, "Polyhedral Mass Properties" (2002)), as
trimesh computes them (``Trimesh.mass_properties``); trimesh (the ``shapes`` extra, ``pip install
stability[shapes]``) also reads the file. A shape model is untrusted input: it is read as a mesh
and nothing else (no pickle, no scene graph of other files), and refused in one line when it is
missing, of another format, open (not watertight), with inconsistent or inward-facing facets, or
of zero or negative volume. trimesh has no test for self-intersection without python-fcl; a mesh
that crosses itself but is closed and consistently wound is not caught here.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..core.body import RigidBody
from ..util.checks import positive_float, real_array

#: The file formats read (trimesh's loaders for them).
FORMATS = ("obj", "stl", "ply", "off")


@dataclass(frozen=True)
class MassProperties:
    """Mass properties of a uniform solid, in the units of its mesh (length L, density rho).

    Attributes
    ----------
    volume : float
        L^3.
    mass : float
        rho L^3.
    center_of_mass : ndarray, shape (3,)
        L, in the mesh's frame.
    inertia : ndarray, shape (3, 3)
        Inertia tensor about the centre of mass, mesh axes, rho L^5.
    moments : ndarray, shape (3,)
        Principal moments, ascending, rho L^5.
    axes : ndarray, shape (3, 3)
        Principal axes as columns (a proper rotation), ``inertia = axes diag(moments) axes^T``.
    """

    volume: float
    mass: float
    center_of_mass: np.ndarray
    inertia: np.ndarray
    moments: np.ndarray
    axes: np.ndarray

    def body(self, name: str = "shape model") -> RigidBody:
        """The :class:`~stability.RigidBody` of the principal moments (axes ascending)."""
        return RigidBody(*self.moments, name=name)


def _trimesh():
    try:
        import trimesh
    except ImportError:
        raise ImportError("reading shape models needs trimesh: pip install 'stability[shapes]'"
                          ) from None
    return trimesh


def load_mesh(path):
    """A shape model file read as one triangle mesh (a ``trimesh.Trimesh``), checked.

    Parameters
    ----------
    path : str or Path
        An OBJ, STL, PLY or OFF file.
    """
    trimesh = _trimesh()
    p = Path(path)
    kind = p.suffix.lower().lstrip(".")
    if kind not in FORMATS:
        raise ValueError(f"{p}: a shape model must be one of {', '.join(FORMATS)} (by its "
                         f"suffix), got {p.suffix or 'no suffix'!r}")
    if not p.is_file():
        raise ValueError(f"{p}: no such file")
    try:
        with open(p, "rb") as stream:
            mesh = trimesh.load(stream, file_type=kind, force="mesh", process=True)
    except Exception as exc:  # a parser's error, whatever its type, is the file's fault
        raise ValueError(f"{p}: not a readable {kind.upper()} mesh ({type(exc).__name__}: "
                         f"{str(exc).splitlines()[0] if str(exc) else 'no detail'})") from None
    if not isinstance(mesh, trimesh.Trimesh) or len(mesh.faces) == 0:
        raise ValueError(f"{p}: holds no triangles; a shape model is a closed triangle mesh")
    return _checked(mesh, str(p))


def _checked(mesh, where: str):
    """``mesh`` if it bounds a solid; else a one-line ValueError saying what to fix."""
    if not np.all(np.isfinite(mesh.vertices)):
        raise ValueError(f"{where}: vertices that are not finite numbers; fix the file")
    if not mesh.is_watertight:
        raise ValueError(f"{where}: the mesh is open or has edges shared by more than two "
                         f"facets (not watertight: {len(mesh.faces)} facets); close its holes "
                         "(e.g. trimesh.repair.fill_holes) or export a closed solid")
    if not mesh.is_winding_consistent:
        raise ValueError(f"{where}: facets wound inconsistently (neighbours disagree on which "
                         "side is out); fix the normals (trimesh.repair.fix_winding)")
    if not mesh.volume > 0.0:
        raise ValueError(f"{where}: the facets face inwards (signed volume {mesh.volume:.6g} "
                         "<= 0); invert them (trimesh.repair.fix_inversion)")
    return mesh


def mesh_from_arrays(vertices, faces):
    """A checked ``trimesh.Trimesh`` from vertices (V, 3) and triangles (F, 3)."""
    trimesh = _trimesh()
    v = real_array("vertices", vertices)
    f = np.asarray(faces)
    if v.ndim != 2 or v.shape[1] != 3 or f.ndim != 2 or f.shape[1] != 3 or len(f) == 0:
        raise ValueError(f"a mesh is vertices (V, 3) and faces (F, 3), got {v.shape} and "
                         f"{f.shape}")
    if not np.issubdtype(f.dtype, np.integer) or f.min() < 0 or f.max() >= len(v):
        raise ValueError(f"faces must index the {len(v)} vertices with integers")
    return _checked(trimesh.Trimesh(v, f, process=True), "mesh")


def mass_properties(shape, density: float = 1.0) -> MassProperties:
    """Mass properties of a closed mesh of uniform ``density`` (module docstring).

    Parameters
    ----------
    shape : str, Path, (vertices, faces) or trimesh.Trimesh
        A shape-model file, arrays, or a mesh.
    density : float
        Mass per unit volume (kg m^-3 for a mesh in metres).

    Returns
    -------
    MassProperties
    """
    rho = positive_float("density", density)
    if isinstance(shape, (str, Path)):
        mesh = load_mesh(shape)
    elif isinstance(shape, tuple) and len(shape) == 2:
        mesh = mesh_from_arrays(*shape)
    else:
        mesh = _checked(shape, "mesh") if hasattr(shape, "is_watertight") else None
        if mesh is None:
            raise ValueError(f"shape must be a file, (vertices, faces) or a trimesh.Trimesh, "
                             f"got {type(shape).__name__}")
    props = mesh.mass_properties  # unit density, inertia about the centre of mass
    J = np.asarray(props["inertia"], float) * rho
    J = 0.5 * (J + J.T)
    moments, axes = np.linalg.eigh(J)
    if np.linalg.det(axes) < 0.0:
        axes[:, 2] = -axes[:, 2]
    return MassProperties(float(props["volume"]), float(props["volume"]) * rho,
                          np.asarray(props["center_mass"], float), J, moments, axes)


__all__ = ["FORMATS", "MassProperties", "load_mesh", "mass_properties", "mesh_from_arrays"]
