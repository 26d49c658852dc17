"""The variance benchmark's scene suite, each written once and turned into both a caustic scene
(JSON) and a Mitsuba 3 scene (a dict for mi.load_dict) that describe the same thing:

- geometry as 4x4 matrices (caustic's `matrix` transform, Mitsuba's `to_world`): caustic's quad
  is Mitsuba's `rectangle` ([-1, 1]^2 at z = 0, front +z), both spheres are the unit sphere;
- the same camera (fov along x, a box pixel filter), bounce count (caustic's max_depth N is
  Mitsuba's N + 1: Mitsuba counts the camera ray's vertex), thin lens (round aperture, the plane
  of focus at the same distance along the view direction);
- materials: diffuse (Lambert), GGX conductors with the same complex IOR, GGX dielectrics with
  the same IOR (Mitsuba's roughconductor / roughdielectric, distribution "ggx");
- lights: a rect light is a one-sided `rectangle` with an `area` emitter and a black BSDF (in
  caustic a rect light's surface absorbs); sphere lights likewise; point lights in intensity;
- environments: `constant`, and `envmap`. Mitsuba's equirectangular mapping is caustic's
  (docs/scene-format.md) turned by 180 degrees about +y: the brightest texel of assets/sky.hdr,
  direction d in caustic, is where Mitsuba's envmap returns it for (-d.x, d.y, -d.z) (measured
  with the emitter's eval), so the Mitsuba map gets to_world = rotate(+y, 180). Mitsuba looks a
  map up with its texels at the grid's vertices (u = i / W, v = j / (H - 1)), caustic at their
  centres (u = (i + 1/2) / W, v = (j + 1/2) / H): under assets/sky.hdr image means differ by
  about 0.4 % for that alone (docs/performance.md).
"""
import math
import os
import sys

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


def trs(translate=(0, 0, 0), rotate=(0, 0, 0), scale=1.0):
    """caustic's M = T * Rz * Ry * Rx * S (docs/scene-format.md, Transforms)."""
    s = np.diag(list(np.broadcast_to(np.asarray(scale, float), 3)) + [1.0])
    def rot(axis, deg):
        a = math.radians(deg)
        c, s_ = math.cos(a), math.sin(a)
        m = np.eye(4)
        i, j = [(1, 2), (2, 0), (0, 1)][axis]
        m[i, i], m[i, j], m[j, i], m[j, j] = c, -s_, s_, c
        return m
    t = np.eye(4)
    t[:3, 3] = translate
    return t @ rot(2, rotate[2]) @ rot(1, rotate[1]) @ rot(0, rotate[0]) @ s


def diffuse(albedo):
    return {"type": "diffuse", "albedo": list(albedo)}


def conductor(eta, k, alpha):
    return {"type": "conductor", "eta": list(eta), "k": list(k), "roughness": alpha}


def dielectric(ior, alpha=0.0):
    return {"type": "dielectric", "ior": ior, "roughness": alpha}


# Gold's complex IOR at R, G, B: caustic's "gold" preset (renderer/gpu_scene.cpp).
GOLD = ((0.183, 0.421, 1.373), (3.424, 2.346, 1.770))


def floor_and(objects, floor_albedo=(0.5, 0.5, 0.5), size=6.0):
    return [{"shape": "quad", "material": diffuse(floor_albedo),
             "matrix": trs(rotate=(-90, 0, 0), scale=size)}] + objects


def suite():
    """name -> scene description (see to_caustic / to_mitsuba)."""
    s = {}
    cam = {"position": (0, 1.2, 4.5), "look_at": (0, 0.5, 0), "up": (0, 1, 0), "fov": 40}
    # The Cornell box is caustic's own file and Mitsuba's cornell_box() (the same numbers).
    s["cornell"] = {"cornell": True, "width": 128, "height": 128, "max_depth": 7}
    # The throughput benchmark's mesh scene (issue 16): caustic's own file, translated for Mitsuba
    # by tests/gpu_machine/mitsuba_bench.py (square images only).
    s["knot"] = {"file": os.path.join(ROOT, "scenes", "mesh-knot.json"), "width": 128, "height": 128, "max_depth": 7}
    s["rough"] = {
        "width": 128, "height": 128, "max_depth": 7, "camera": cam,
        "objects": floor_and([
            {"shape": "sphere", "material": conductor(*GOLD, 0.2), "matrix": trs((-0.65, 0.6, 0), scale=0.6)},
            {"shape": "sphere", "material": dielectric(1.5, 0.2), "matrix": trs((0.65, 0.6, 0), scale=0.6)},
        ]),
        "lights": [{"type": "rect", "color": (8, 8, 8), "matrix": trs((0.5, 3, 1.5), (115, 0, 0), (0.6, 0.6, 1))}],
        "environment": {"type": "constant", "radiance": (0.25, 0.25, 0.25)},
    }
    # Direct lighting alone (max depth 1): a diffuse, a rough metal and a rough glass sphere
    # under a rect light, the 4-D integral (pixel, light) that stratification helps most.
    s["direct"] = {
        "width": 128, "height": 128, "max_depth": 1, "camera": cam,
        "objects": floor_and([
            {"shape": "sphere", "material": diffuse((0.7, 0.7, 0.7)), "matrix": trs((-1.1, 0.45, 0), scale=0.45)},
            {"shape": "sphere", "material": conductor(*GOLD, 0.3), "matrix": trs((0, 0.45, 0), scale=0.45)},
            {"shape": "sphere", "material": diffuse((0.2, 0.4, 0.7)), "matrix": trs((1.1, 0.45, 0), scale=0.45)},
        ]),
        "lights": [{"type": "rect", "color": (6, 6, 6), "matrix": trs((-0.5, 2.5, 1.0), (110, 0, 0), (0.8, 0.5, 1))}],
        "environment": {"type": "none"},
    }
    s["envmap"] = {
        "width": 128, "height": 128, "max_depth": 7, "camera": cam,
        "objects": floor_and([
            {"shape": "sphere", "material": diffuse((0.8, 0.8, 0.8)), "matrix": trs((-0.7, 0.55, 0), scale=0.55)},
            {"shape": "sphere", "material": conductor(*GOLD, 0.1), "matrix": trs((0.7, 0.55, 0), scale=0.55)},
        ], size=4.0),
        "lights": [],
        "environment": {"type": "map", "file": os.path.join(ROOT, "assets", "sky.hdr"), "intensity": 1.0},
    }
    s["dof"] = {
        "width": 128, "height": 128, "max_depth": 7,
        "camera": {"position": (0, 0.8, 5), "look_at": (0, 0.5, 0), "up": (0, 1, 0), "fov": 35,
                   "aperture": 0.15, "focus_distance": 5.0},
        "objects": floor_and([
            {"shape": "sphere", "material": diffuse((0.1, 0.55, 0.55)), "matrix": trs((-1.0, 0.4, 2.2), scale=0.4)},
            {"shape": "sphere", "material": diffuse((0.8, 0.8, 0.8)), "matrix": trs((0, 0.5, 0), scale=0.5)},
            {"shape": "sphere", "material": diffuse((0.85, 0.35, 0.08)), "matrix": trs((1.1, 0.5, -2.5), scale=0.5)},
        ], size=20.0),
        "lights": [{"type": "sphere", "color": (300, 250, 200), "position": (1.5, 2.5, 1.5), "radius": 0.08}],
        "environment": {"type": "constant", "radiance": (0.1, 0.1, 0.12)},
    }
    s["caustic"] = {
        "width": 128, "height": 128, "max_depth": 7, "camera": cam,
        "objects": floor_and([
            {"shape": "sphere", "material": dielectric(1.5), "matrix": trs((0, 0.6, 0), scale=0.6)},
        ]),
        "lights": [{"type": "sphere", "color": (400, 400, 400), "position": (0.8, 2.6, -0.6), "radius": 0.08}],
        "environment": {"type": "none"},
    }
    # Many small lights: a 16 x 16 grid of sphere lights of different colours and strengths over a
    # floor with three spheres.
    rng = np.random.default_rng(7)
    lights = []
    for i in range(16):
        for j in range(16):
            c = rng.uniform(0.2, 1.0, 3) * rng.choice([5.0, 20.0, 80.0])
            lights.append({"type": "sphere", "color": tuple(float(x) for x in c),
                           "position": (-3.0 + 6.0 * (i + 0.5) / 16, 0.9 + 0.3 * rng.uniform(),
                                        -3.0 + 6.0 * (j + 0.5) / 16), "radius": 0.02})
    s["manylights"] = {
        "width": 128, "height": 128, "max_depth": 7,
        "camera": {"position": (0, 2.5, 5.5), "look_at": (0, 0.3, 0), "up": (0, 1, 0), "fov": 45},
        "objects": floor_and([
            {"shape": "sphere", "material": diffuse((0.8, 0.8, 0.8)), "matrix": trs((-1.2, 0.4, 0.5), scale=0.4)},
            {"shape": "sphere", "material": conductor(*GOLD, 0.2), "matrix": trs((0.2, 0.45, -0.4), scale=0.45)},
            {"shape": "sphere", "material": diffuse((0.3, 0.5, 0.8)), "matrix": trs((1.3, 0.35, 0.8), scale=0.35)},
        ], size=4.0),
        "lights": lights,
        "environment": {"type": "none"},
    }
    return s


def _matrix_list(m):
    return [float(x) for x in np.asarray(m).reshape(-1)]


def to_caustic(scene):
    """A caustic scene dict (or the path of scenes/cornell-box.json and overrides)."""
    if scene.get("cornell") or scene.get("file"):
        return None
    mats, objects = [], []
    def material(spec):
        name = "m%d" % len(mats)
        m = {"name": name, "type": spec["type"]}
        if spec["type"] == "diffuse":
            m["albedo"] = spec["albedo"]
        elif spec["type"] == "conductor":
            m.update(metal="custom", eta=spec["eta"], k=spec["k"], roughness=spec["roughness"])
        elif spec["type"] == "dielectric":
            m.update(ior=spec["ior"], roughness=spec["roughness"])
        mats.append(m)
        return name
    for o in scene["objects"]:
        objects.append({"shape": o["shape"], "material": material(o["material"]),
                        "transform": {"matrix": _matrix_list(o["matrix"])}})
    lights = []
    for l in scene["lights"]:
        if l["type"] == "rect":
            lights.append({"type": "rect", "color": list(l["color"]), "transform": {"matrix": _matrix_list(l["matrix"])}})
        elif l["type"] == "sphere":
            lights.append({"type": "sphere", "color": list(l["color"]), "position": list(l["position"]), "radius": l["radius"]})
        elif l["type"] == "point":
            lights.append({"type": "point", "color": list(l["color"]), "position": list(l["position"])})
    c = scene["camera"]
    camera = {"position": list(c["position"]), "look_at": list(c["look_at"]), "up": list(c["up"]),
              "fov": c["fov"], "fov_axis": "x"}
    if c.get("aperture"):
        camera.update(aperture_radius=c["aperture"], focal_distance=c["focus_distance"])
    env = dict(scene["environment"])
    if "radiance" in env:
        env["radiance"] = list(env["radiance"])
    return {"version": 1, "camera": camera,
            "render": {"width": scene["width"], "height": scene["height"], "max_depth": scene["max_depth"],
                       "filter": "box"},
            "materials": mats, "objects": objects, "lights": lights, "environment": env}


def to_mitsuba(mi, scene, spp):
    """A dict for mi.load_dict describing the same scene (`mi` is the imported mitsuba module)."""
    T = mi.ScalarTransform4f
    film = {"type": "hdrfilm", "width": scene["width"], "height": scene["height"],
            "rfilter": {"type": "box"}, "pixel_format": "rgb"}
    integrator = {"type": "path", "max_depth": scene["max_depth"] + 1}
    if scene.get("file"):
        sys.path.insert(0, os.path.join(ROOT, "tests", "gpu_machine"))
        import mitsuba_bench
        assert scene["width"] == scene["height"], "mitsuba_bench translates square images only"
        return mitsuba_bench.from_caustic(mi, scene["file"], scene["width"], spp, scene["max_depth"])
    if scene.get("cornell"):
        d = mi.cornell_box()
        d["sensor"]["film"].update(film)
        d["sensor"]["sampler"] = {"type": "independent", "sample_count": spp}
        d["integrator"] = integrator
        return d
    def rgb(v):
        return {"type": "rgb", "value": [float(x) for x in v]}
    def bsdf(spec):
        if spec["type"] == "diffuse":
            return {"type": "diffuse", "reflectance": rgb(spec["albedo"])}
        if spec["type"] == "conductor":
            return {"type": "roughconductor", "distribution": "ggx", "alpha": spec["roughness"],
                    "eta": rgb(spec["eta"]), "k": rgb(spec["k"])}
        if spec["roughness"] > 0:
            return {"type": "roughdielectric", "distribution": "ggx", "alpha": spec["roughness"],
                    "int_ior": spec["ior"], "ext_ior": 1.0}
        return {"type": "dielectric", "int_ior": spec["ior"], "ext_ior": 1.0}
    black = {"type": "diffuse", "reflectance": rgb((0, 0, 0))}
    c = scene["camera"]
    sensor = {"type": "perspective", "fov": c["fov"], "fov_axis": "x",
              "to_world": T.look_at(origin=list(c["position"]), target=list(c["look_at"]), up=list(c["up"])),
              "film": film, "sampler": {"type": "independent", "sample_count": spp}}
    if c.get("aperture"):
        sensor.update(type="thinlens", aperture_radius=c["aperture"], focus_distance=c["focus_distance"])
    d = {"type": "scene", "integrator": integrator, "sensor": sensor}
    for i, o in enumerate(scene["objects"]):
        d["obj%d" % i] = {"type": {"quad": "rectangle", "sphere": "sphere"}[o["shape"]],
                          "to_world": T(np.asarray(o["matrix"]).tolist()), "bsdf": bsdf(o["material"])}
    for i, l in enumerate(scene["lights"]):
        if l["type"] == "rect":
            d["light%d" % i] = {"type": "rectangle", "to_world": T(np.asarray(l["matrix"]).tolist()), "bsdf": black,
                                "emitter": {"type": "area", "radiance": rgb(l["color"])}}
        elif l["type"] == "sphere":
            d["light%d" % i] = {"type": "sphere", "center": list(l["position"]), "radius": l["radius"], "bsdf": black,
                                "emitter": {"type": "area", "radiance": rgb(l["color"])}}
        elif l["type"] == "point":
            d["light%d" % i] = {"type": "point", "position": list(l["position"]), "intensity": rgb(l["color"])}
    env = scene["environment"]
    if env["type"] == "constant":
        d["env"] = {"type": "constant", "radiance": rgb(env["radiance"])}
    elif env["type"] == "map":
        d["env"] = {"type": "envmap", "filename": env["file"], "scale": env.get("intensity", 1.0),
                    "to_world": T().rotate([0, 1, 0], 180)}
    return d
