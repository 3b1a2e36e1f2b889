#!/usr/bin/env python3
"""Build scenes/gltf/trimesh-export.glb with trimesh (a third-party glTF exporter).

The output is a small binary glTF test asset for the ggx glTF loader. It exercises:

* node hierarchy: a transform-only "group" node with two children, one of them
  rotated (trimesh writes every non-identity node transform as a 4x4 `matrix`
  and omits identity ones, e.g. on "ground");
* metallic-roughness factors: a gold-ish metal icosphere (metallicFactor 1,
  roughnessFactor 0.3, smooth per-vertex normals);
* a base-colour texture: a box with a generated 16x16 checker PNG and
  per-face UVs (24 vertices);
* a normal map with an explicit TANGENT attribute: a ground plane with a
  generated "bumps" normal map (OpenGL / glTF +Y-up convention);
* emission: a downward-facing quad with emissiveFactor and a black base colour
  (a light panel for a path tracer);
* a perspective camera (trimesh writes exactly one, attached to its own node).

All geometry is indexed TRIANGLES (uint32 indices, `"mode": 4` written
explicitly). trimesh writes no `sampler` on its textures (=> glTF default
sampler: repeat wrap, filtering up to the implementation) and no KHR_*
extensions. Other details of trimesh's output that a loader test may meet:

* UVs are written as (u, 1 - v), so the ground's TEXCOORD_0 spans v in [-3, 1];
* colour factors are quantised to 8 bits (0.55 -> 140/255 = 0.5490196...);
* the camera gets aspectRatio 4/3, yfov = 37.5 degrees and no zfar (infinite);
* identical buffers are shared: the light quad uses the ground's index accessor;
* asset.generator is "https://github.com/mikedh/trimesh".

About TANGENT: trimesh has no first-class tangent support; it exports any
per-vertex attribute in `mesh.vertex_attributes` as an application-specific
attribute with a leading underscore (`_TANGENT`). The `tree_postprocessor`
hook of trimesh's exporter (part of its public API) renames `_TANGENT` to the
core `TANGENT` semantic. The accessor itself (VEC4 float32, w = +1) is written
by trimesh unchanged. Everything else in the file is trimesh's own output.

Usage (run in scenes/gltf/; the output always goes next to this file):

    python3 -m venv v && v/bin/pip install trimesh numpy pillow && v/bin/python make_trimesh_glb.py

and then delete the v/ folder. The trimesh-export.glb in this folder (14300
bytes) was made with Python 3.11.7, trimesh 5.2.0, numpy 2.4.6 and pillow
13.0.0. The script has no randomness: re-running it with those versions
rewrites a byte-identical file. Other trimesh versions may write different
(still valid) bytes.
"""

from __future__ import annotations

import os

import numpy as np
import trimesh
from PIL import Image
from trimesh.visual.material import PBRMaterial
from trimesh.visual.texture import TextureVisuals

HERE = os.path.dirname(os.path.abspath(__file__))
OUT = os.path.join(HERE, "trimesh-export.glb")


def checker_image(n: int = 16, cells: int = 4) -> Image.Image:
    """n x n RGB checker with `cells` x `cells` squares (orange / off-white)."""
    ij = np.indices((n, n)) // (n // cells)
    odd = ((ij[0] + ij[1]) % 2).astype(bool)
    img = np.empty((n, n, 3), np.uint8)
    img[odd] = (230, 120, 30)
    img[~odd] = (235, 235, 225)
    return Image.fromarray(img, "RGB")


def bumps_normal_map(n: int = 64, bumps: int = 4) -> Image.Image:
    """Tangent-space normal map of a grid of smooth round bumps.

    Encoded as glTF expects: rgb = (normal * 0.5 + 0.5) * 255 with +X to the
    right of the image and +Y towards the top of the image (OpenGL style).
    """
    # pixel centres in [0, 1); row 0 is the top of the image
    c = (np.arange(n) + 0.5) / n
    x = c[None, :]  # to the right
    y = 1.0 - c[:, None]  # up
    cell = 1.0 / bumps
    fx = (x % cell) / cell - 0.5  # [-0.5, 0.5) within each cell
    fy = (y % cell) / cell - 0.5
    r2 = fx * fx + fy * fy
    inside = r2 < 0.16  # radius 0.4 of a cell
    amp = 0.6
    # height h = amp * (0.16 - r2)^2 inside the disc; slopes in cell units
    dh = np.where(inside, -4.0 * amp * (0.16 - r2), 0.0)
    dhdx = dh * fx
    dhdy = dh * fy
    nrm = np.stack([-dhdx, -dhdy, np.ones_like(dhdx)], axis=-1)
    nrm /= np.linalg.norm(nrm, axis=-1, keepdims=True)
    rgb = np.round((nrm * 0.5 + 0.5) * 255.0).astype(np.uint8)
    return Image.fromarray(rgb, "RGB")


def textured_box(size: float = 0.8) -> trimesh.Trimesh:
    """Axis-aligned cube with 24 vertices and a full [0,1]^2 UV square per face."""
    h = size / 2.0
    # (normal, u axis, v axis) per face; v is "up" in trimesh's UV convention
    faces_def = [
        ((1, 0, 0), (0, 0, -1), (0, 1, 0)),
        ((-1, 0, 0), (0, 0, 1), (0, 1, 0)),
        ((0, 1, 0), (1, 0, 0), (0, 0, -1)),
        ((0, -1, 0), (1, 0, 0), (0, 0, 1)),
        ((0, 0, 1), (1, 0, 0), (0, 1, 0)),
        ((0, 0, -1), (-1, 0, 0), (0, 1, 0)),
    ]
    verts, norms, uvs, tris = [], [], [], []
    for nrm, uax, vax in faces_def:
        nrm, uax, vax = (np.array(a, float) for a in (nrm, uax, vax))
        base = len(verts)
        for u, v in ((0, 0), (1, 0), (1, 1), (0, 1)):
            verts.append(h * (nrm + (2 * u - 1) * uax + (2 * v - 1) * vax))
            norms.append(nrm)
            uvs.append((u, v))
        tris += [(base, base + 1, base + 2), (base, base + 2, base + 3)]
    mat = PBRMaterial(
        name="checker",
        baseColorTexture=checker_image(),
        metallicFactor=0.0,
        roughnessFactor=0.6,
    )
    return trimesh.Trimesh(
        vertices=np.array(verts),
        faces=np.array(tris),
        vertex_normals=np.array(norms),
        visual=TextureVisuals(uv=np.array(uvs, float), material=mat),
        process=False,
    )


def metal_sphere() -> trimesh.Trimesh:
    mesh = trimesh.creation.icosphere(subdivisions=2, radius=0.5)
    # exact smooth normals of a sphere (also avoids trimesh's scipy code path)
    mesh.vertex_normals = mesh.vertices / np.linalg.norm(mesh.vertices, axis=1)[:, None]
    mesh.visual = TextureVisuals(
        material=PBRMaterial(
            name="gold",
            baseColorFactor=[1.0, 0.78, 0.34, 1.0],
            metallicFactor=1.0,
            roughnessFactor=0.3,
        )
    )
    return mesh


def ground_plane(half: float = 2.0) -> trimesh.Trimesh:
    """Quad in y = 0 facing +Y, tiled UVs, normal map plus TANGENT."""
    verts = np.array(
        [[-half, 0, half], [half, 0, half], [half, 0, -half], [-half, 0, -half]], float
    )
    # trimesh UV convention: v grows towards the top of the image; here the
    # image top points to -Z. 4x tiling exercises REPEAT wrapping.
    uvs = np.array([[0, 0], [4, 0], [4, 4], [0, 4]], float)
    tris = np.array([[0, 1, 2], [0, 2, 3]])
    normals = np.tile([0.0, 1.0, 0.0], (4, 1))
    # dP/du = +X; dP/dv (image up) = -Z; cross(N, T) = cross(+Y, +X) = -Z => w = +1
    tangents = np.tile([1.0, 0.0, 0.0, 1.0], (4, 1)).astype(np.float32)
    mat = PBRMaterial(
        name="bumpy-ground",
        baseColorFactor=[0.55, 0.55, 0.55, 1.0],
        metallicFactor=0.0,
        roughnessFactor=0.8,
        normalTexture=bumps_normal_map(),
    )
    mesh = trimesh.Trimesh(
        vertices=verts,
        faces=tris,
        vertex_normals=normals,
        visual=TextureVisuals(uv=uvs, material=mat),
        process=False,
    )
    mesh.vertex_attributes["TANGENT"] = tangents  # exported as "_TANGENT"
    return mesh


def light_panel(half: float = 0.5) -> trimesh.Trimesh:
    """Quad facing -Y (downwards) with an emissive material."""
    verts = np.array(
        [[-half, 0, -half], [half, 0, -half], [half, 0, half], [-half, 0, half]], float
    )
    tris = np.array([[0, 1, 2], [0, 2, 3]])  # CCW seen from below => normal -Y
    mesh = trimesh.Trimesh(
        vertices=verts,
        faces=tris,
        vertex_normals=np.tile([0.0, -1.0, 0.0], (4, 1)),
        process=False,
    )
    mesh.visual = TextureVisuals(
        material=PBRMaterial(
            name="emitter",
            baseColorFactor=[0.0, 0.0, 0.0, 1.0],
            emissiveFactor=[1.0, 0.85, 0.6],
            metallicFactor=0.0,
            roughnessFactor=1.0,
        )
    )
    return mesh


def rename_tangent(tree: dict) -> None:
    """trimesh tree_postprocessor: `_TANGENT` -> core `TANGENT` semantic."""
    for mesh in tree.get("meshes", []):
        for prim in mesh.get("primitives", []):
            attrs = prim.get("attributes", {})
            if "_TANGENT" in attrs:
                attrs["TANGENT"] = attrs.pop("_TANGENT")


def translation(x: float, y: float, z: float) -> np.ndarray:
    return trimesh.transformations.translation_matrix([x, y, z])


def build_scene() -> trimesh.Scene:
    scene = trimesh.Scene()
    scene.add_geometry(ground_plane(), geom_name="ground", node_name="ground")
    # transform-only parent node
    scene.graph.update(frame_from="world", frame_to="group", matrix=translation(0, 0.5, 0))
    scene.add_geometry(
        metal_sphere(),
        geom_name="sphere",
        node_name="sphere",
        parent_node_name="group",
        transform=translation(-0.7, 0.0, 0.0),
    )
    box_xf = translation(0.7, -0.1, 0.0) @ trimesh.transformations.rotation_matrix(
        np.radians(30.0), [0, 1, 0]
    )
    scene.add_geometry(
        textured_box(),
        geom_name="box",
        node_name="box",
        parent_node_name="group",
        transform=box_xf,
    )
    scene.add_geometry(
        light_panel(), geom_name="light", node_name="light", transform=translation(0, 2.5, 0)
    )
    # perspective camera looking at the group from +Z, slightly above
    # explicit camera: the lazily created default one gets a random name
    scene.camera = trimesh.scene.Camera(name="camera", fov=(50.0, 37.5), z_near=0.05)
    cam = trimesh.transformations.rotation_matrix(np.radians(-15.0), [1, 0, 0])
    cam = translation(0.0, 1.6, 4.2) @ cam
    scene.camera_transform = cam
    return scene


def main() -> None:
    scene = build_scene()
    data = trimesh.exchange.gltf.export_glb(
        scene, include_normals=True, tree_postprocessor=rename_tangent
    )
    with open(OUT, "wb") as f:
        f.write(data)
    print(f"wrote {OUT} ({len(data)} bytes) with trimesh {trimesh.__version__}")


if __name__ == "__main__":
    main()
