#!/usr/bin/env python3
"""Writes the small meshes of tests/fixtures/, tests/scripts/assets/ and scripts/scenes/assets/
(ours, made here).

    python3 tools/make_meshes.py        # rewrites them in place

Every closed mesh is checked before it is written: each edge is shared by exactly two
triangles, the triangles wind counter-clockwise seen from outside (positive signed volume).
Sizes are in metres, Y up.

  tests/fixtures/cube.obj          0.2 m cube centred on the origin, six quads (12 triangles)
  tests/fixtures/open_box.obj      the same cube without its top face (4 open edges)
  tests/fixtures/cup.obj           a closed, watertight cup: a solid of revolution, 24 segments,
                                   outer radius 0.1, height 0.12, wall and bottom 0.03 thick
  tests/fixtures/tetrahedron.gltf  a regular tetrahedron (corners of a 0.1 m cube), its node
                                   moved up 0.05 m; the buffer inline as a data: URI
  tests/fixtures/tetrahedron.glb   binary glTF: that tetrahedron twice, nodes at x = -0.1 and
                                   x = +0.1 (two placed meshes merged into one)
  tests/fixtures/not_a_mesh.txt    text, not a mesh format
  tests/fixtures/mesh_root/buffer_in_parent_folder.gltf
                                   the tetrahedron.gltf tetrahedron with its buffer in a file of the folder
                                   above, "../tetrahedron_buffer.bin": refused with the root mesh_root/,
                                   loads with the root tests/fixtures/ (eng_mesh_file_options.root)
  tests/fixtures/tetrahedron_buffer.bin   that buffer
  tests/fixtures/hostile_ply_header_hangs_assimp.ply   a PLY header cut off in "propert": assimp 5.2
                                   loops for ever on it (eng_mesh_file_options.timeout_s)
  tests/fixtures/hostile_csm_crashes_assimp.csm        a broken CSM that crashes assimp 5.2 (SIGSEGV)
  scripts/scenes/assets/boat.obj   a small boat hull, 0.6 m long, with a deck (closed), keel on y = 0
  tests/scripts/assets/            cube.obj, open_box.obj, cup.obj and boat.obj again, for the script tests
                                   (a sandboxed scene reads meshes from its own folder and below)
"""
import base64
import json
import math
import os
import struct

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..")


def check_closed(name, verts, tris):
    edges = {}
    for t in tris:
        for a, b in ((t[0], t[1]), (t[1], t[2]), (t[2], t[0])):
            edges[(a, b)] = edges.get((a, b), 0) + 1
    for (a, b), n in edges.items():
        assert n == 1 and edges.get((b, a), 0) == 1, f"{name}: edge {a}-{b} is not shared by two triangles"
    vol = 0.0
    for t in tris:
        p, q, r = (verts[i] for i in t)
        vol += (p[0] * (q[1] * r[2] - q[2] * r[1]) - p[1] * (q[0] * r[2] - q[2] * r[0])
                + p[2] * (q[0] * r[1] - q[1] * r[0])) / 6.0
    assert vol > 0, f"{name}: triangles wind inwards (volume {vol})"
    return vol


def write_obj(rel, comment, verts, faces):
    path = os.path.join(ROOT, rel)
    os.makedirs(os.path.dirname(path), exist_ok=True)
    with open(path, "w") as f:
        f.write("# " + comment + "\n# Written by tools/make_meshes.py (Seiche's own; metres, Y up).\n")
        f.write("o " + os.path.splitext(os.path.basename(rel))[0] + "\n")
        for v in verts:
            f.write("v %s %s %s\n" % tuple(num(c) for c in v))
        for face in faces:
            f.write("f " + " ".join(str(i + 1) for i in face) + "\n")


def num(c):
    """A coordinate as short text: 7 decimals, no '-0'."""
    t = ("%.7f" % c).rstrip("0").rstrip(".")
    return "0" if t in ("-0", "") else t


def triangles(faces):
    out = []
    for face in faces:
        for k in range(1, len(face) - 1):
            out.append((face[0], face[k], face[k + 1]))
    return out


def cube(half):
    verts = [((1 if k & 1 else -1) * half, (1 if k & 2 else -1) * half, (1 if k & 4 else -1) * half) for k in range(8)]
    # Quads counter-clockwise seen from outside: -x, +x, -y, +y, -z, +z.
    faces = [(0, 4, 6, 2), (1, 3, 7, 5), (0, 1, 5, 4), (2, 6, 7, 3), (0, 2, 3, 1), (4, 5, 7, 6)]
    return verts, faces


def cup(n=24, r_out=0.1, height=0.12, wall=0.03, bottom=0.03):
    # Profile from the outer bottom round to the inner bottom; each ring of n vertices.
    r_in = r_out - wall
    profile = [(r_out, 0.0), (r_out, height), (r_in, height), (r_in, bottom)]
    verts = [(0.0, 0.0, 0.0)]
    for r, y in profile:
        for k in range(n):
            a = 2.0 * math.pi * k / n
            verts.append((r * math.cos(a), y, -r * math.sin(a)))
    verts.append((0.0, bottom, 0.0))
    ring = lambda j, k: 1 + j * n + k % n
    top = len(verts) - 1
    faces = []
    for k in range(n):  # outer bottom, seen from below
        faces.append((0, ring(0, k + 1), ring(0, k)))
    for j in range(len(profile) - 1):
        for k in range(n):
            faces.append((ring(j, k), ring(j, k + 1), ring(j + 1, k + 1)))
            faces.append((ring(j, k), ring(j + 1, k + 1), ring(j + 1, k)))
    for k in range(n):  # inner bottom, seen from above
        faces.append((top, ring(3, k), ring(3, k + 1)))
    return verts, faces


def boat(stations=9, length=0.6, beam=0.2, depth=0.1):
    # Cross-sections from the stern (x = -length/2) to the bow; each section five points
    # from the port deck edge round under the keel to the starboard deck edge.
    verts, sections = [], []
    for i in range(stations):
        t = i / (stations - 1)
        x = -length / 2 + t * length
        w = beam / 2 * (1.0 - t ** 3 * 0.9) * (0.85 + 0.15 * math.sin(math.pi * min(t * 1.6, 1.0)))
        d = depth * (0.8 + 0.2 * math.sin(math.pi * t)) * (1.0 - 0.5 * t ** 4)
        keel = depth - d
        pts = [(x, depth, -w), (x, keel + 0.35 * d, -0.85 * w), (x, keel, 0.0), (x, keel + 0.35 * d, 0.85 * w),
               (x, depth, w)]
        sections.append(list(range(len(verts), len(verts) + 5)))
        verts.extend(pts)
    faces = []
    for i in range(stations - 1):
        a, b = sections[i], sections[i + 1]
        for k in range(4):
            faces.append((a[k], a[k + 1], b[k + 1], b[k]))
        faces.append((a[4], a[0], b[0], b[4]))  # deck
    s, e = sections[0], sections[-1]
    faces.append((s[0], s[4], s[3], s[2], s[1]))  # transom, seen from behind
    faces.append((e[0], e[1], e[2], e[3], e[4]))  # bow, seen from ahead
    low = min(v[1] for v in verts)  # the keel's lowest point on y = 0
    return [(x, y - low, z) for x, y, z in verts], faces


def fix_winding(verts, faces):
    """Reverses every face when the mesh came out inside out."""
    try:
        check_closed("probe", verts, triangles(faces))
        return faces
    except AssertionError:
        return [tuple(reversed(f)) for f in faces]


def gltf_tetrahedron(nodes):
    a = 0.05
    verts = [(a, a, a), (a, -a, -a), (-a, a, -a), (-a, -a, a)]
    tris = [(0, 1, 2), (0, 3, 1), (0, 2, 3), (1, 3, 2)]
    tris = fix_winding(verts, tris)
    check_closed("tetrahedron", verts, tris)
    pos = b"".join(struct.pack("<3f", *v) for v in verts)
    idx = b"".join(struct.pack("<3H", *t) for t in tris)
    data = pos + idx + b"\0" * ((4 - len(idx) % 4) % 4)
    doc = {
        "asset": {"version": "2.0", "generator": "Seiche tools/make_meshes.py"},
        "scene": 0,
        "scenes": [{"nodes": list(range(len(nodes)))}],
        "nodes": [{"mesh": 0, "translation": list(t)} for t in nodes],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1, "mode": 4}]}],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3",
             "min": [-a, -a, -a], "max": [a, a, a]},
            {"bufferView": 1, "componentType": 5123, "count": 3 * len(tris), "type": "SCALAR"},
        ],
        "bufferViews": [
            {"buffer": 0, "byteOffset": 0, "byteLength": len(pos), "target": 34962},
            {"buffer": 0, "byteOffset": len(pos), "byteLength": len(idx), "target": 34963},
        ],
        "buffers": [{"byteLength": len(data)}],
    }
    return doc, data


def write_gltf(rel, nodes):
    doc, data = gltf_tetrahedron(nodes)
    doc["buffers"][0]["uri"] = "data:application/octet-stream;base64," + base64.b64encode(data).decode()
    with open(os.path.join(ROOT, rel), "w") as f:
        json.dump(doc, f, indent=1)
        f.write("\n")


def write_glb(rel, nodes):
    doc, data = gltf_tetrahedron(nodes)
    js = json.dumps(doc, separators=(",", ":")).encode()
    js += b" " * ((4 - len(js) % 4) % 4)
    body = struct.pack("<II", len(js), 0x4E4F534A) + js + struct.pack("<II", len(data), 0x004E4942) + data
    with open(os.path.join(ROOT, rel), "wb") as f:
        f.write(struct.pack("<III", 0x46546C67, 2, 12 + len(body)) + body)


def write_gltf_external(rel, uri, rel_bin):
    doc, data = gltf_tetrahedron([(0.0, 0.05, 0.0)])
    doc["buffers"][0]["uri"] = uri
    with open(os.path.join(ROOT, rel), "w") as f:
        json.dump(doc, f, indent=1)
        f.write("\n")
    with open(os.path.join(ROOT, rel_bin), "wb") as f:
        f.write(data)


# Files that hang or crash assimp 5.2 (found by a hostile review): eng_mesh_file_load must refuse
# them in time, with the process alive.
HOSTILE_PLY = b"ply\nformat ascii 1.0\nelement vertex 1\npropert"
HOSTILE_CSM = (b"$Filename x\n$First\x80rame 1\n$Lastframe 1\n$Order\nA\n$Poin\x00s\n1 0 0 0\n")


def main():
    v, f = cube(0.1)
    check_closed("cube", v, triangles(f))
    for d in ("tests/fixtures", "tests/scripts/assets"):
        write_obj(d + "/cube.obj", "A 0.2 m cube centred on the origin.", v, f)
        write_obj(d + "/open_box.obj", "The 0.2 m cube without its top face: open, 4 open edges.", v,
                  [q for q in f if q != (2, 6, 7, 3)])
    v, f = cup()
    f = fix_winding(v, f)
    vol = check_closed("cup", v, triangles(f))
    for d in ("tests/fixtures", "tests/scripts/assets"):
        write_obj(d + "/cup.obj", "A closed, watertight cup (solid of revolution, 24 segments): outer radius "
                  "0.1, height 0.12, wall and bottom 0.03 m; solid volume %.6g m^3." % vol, v, f)
    write_gltf("tests/fixtures/tetrahedron.gltf", [(0.0, 0.05, 0.0)])
    write_glb("tests/fixtures/tetrahedron.glb", [(-0.1, 0.0, 0.0), (0.1, 0.0, 0.0)])
    with open(os.path.join(ROOT, "tests/fixtures/not_a_mesh.txt"), "w") as fh:
        fh.write("This is not a mesh: a text file for the loader's refusal test.\n")
    os.makedirs(os.path.join(ROOT, "tests/fixtures/mesh_root"), exist_ok=True)
    write_gltf_external("tests/fixtures/mesh_root/buffer_in_parent_folder.gltf", "../tetrahedron_buffer.bin",
                        "tests/fixtures/tetrahedron_buffer.bin")
    for rel, data in (("tests/fixtures/hostile_ply_header_hangs_assimp.ply", HOSTILE_PLY),
                      ("tests/fixtures/hostile_csm_crashes_assimp.csm", HOSTILE_CSM)):
        with open(os.path.join(ROOT, rel), "wb") as fh:
            fh.write(data)
    v, f = boat()
    f = fix_winding(v, f)
    check_closed("boat", v, triangles(f))
    for d in ("scripts/scenes/assets", "tests/scripts/assets"):
        write_obj(d + "/boat.obj", "A small boat hull with a deck, 0.6 m long, 0.2 m beam, about 0.1 m deep; bow "
                  "towards +x, the keel's lowest point at y = 0.", v, f)


if __name__ == "__main__":
    main()
