// Camera rays through a lens system (docs/lenses.md, "The lens camera"): renderer/lens.cpp's
// lensCameraRay in float, with its tables in LensBlock (renderer/lens.cpp, lensUniformBlock).
// In the lens's frame (mm; the axis is z, the scene in front at smaller z, the film behind): a
// film point, a point of its exit-pupil bound (a box in the rear vertex's plane, per film radius,
// turned with the film point), the ray between them traced back to front through every surface
// (the stop's opening a circle, a polygon of `blades` or the aperture image), then carried into the world: the film at
// the camera's position, x along right, y along up, z against the view.
// The weight, cos^4(theta) A / z^2 times the scale that makes its mean 1 at the film's centre, is
// the film's exposure: natural and optical vignetting are the lens's, not painted. With
// dispersion a sample carries one channel (chosen with the lens sample's x) traced at its line
// (C, d, F) and weighs 3 in it, 0 in the others.
#ifndef INTEGRATOR_LENS_CAMERA_GLSL
#define INTEGRATOR_LENS_CAMERA_GLSL
#include "../geometry/intersect.glsl"
#include "aperture.glsl"

layout(std140, binding = BINDING_LENS_UBO) uniform LensBlock {
    vec4 lensInfo;   // x: surfaces, y: the film's z, z: the film's radius (half diagonal), w: weight scale
    vec4 lensFilm;   // x, y: the film's half width and height; z: the rear vertex's z; w: the stop's radius
    vec4 lensStop;   // x: blades (0: round), y: blade rotation (rad), z: 1 with dispersion, w: scene units per mm
    // [2i]: radius (0: flat), vertex z, clear radius, 1 at the stop; [2i + 1]: the index behind it at C, d, F
    vec4 lensSurfaces[2 * LENS_MAX_SURFACES];
    vec4 lensPupil[LENS_PUPIL_BINS];  // the exit pupil's bound per film-radius bin: (x0, y0, x1, y1)
};

// How much of a ray passes the stop at p: 0 or 1 for its circle or polygon, the aperture image's
// transmission where the camera has one.
float lensStopTransmission(vec2 p) {
    float radius = lensFilm.w;
    if (dot(p, p) > radius * radius) return 0.0;
    if (HAS_CAMERA(CAMERA_APERTURE_IMAGE) && frame.aperture.w != 0u) return apertureTransmission(p / radius);
    uint blades = uint(lensStop.x);
    if (blades < 3u) return 1.0;
    float sector = 2.0 * PI / float(blades);
    float k = floor((atan(p.y, p.x) - lensStop.y) / sector);
    float mid = lensStop.y + (k + 0.5) * sector;
    return p.x * cos(mid) + p.y * sin(mid) <= radius * cos(0.5 * sector) ? 1.0 : 0.0;
}

// Through every surface from the film to the front; false where the lens blocks the ray, and
// the stop's transmission in `pass`.
bool lensTrace(inout vec3 o, inout vec3 d, uint channel, out float pass) {
    pass = 1.0;
    uint count = uint(lensInfo.x);
    for (uint step = 0u; step < count; ++step) {
        uint k = count - 1u - step;
        vec4 s = lensSurfaces[2u * k];
        vec3 p, n;
        if (s.x == 0.0) {
            if (abs(d.z) < 1e-12) return false;
            float t = (s.y - o.z) / d.z;
            if (t <= 0.0) return false;
            p = o + t * d;
            n = vec3(0.0, 0.0, 1.0);
        } else {
            // The sphere of the surface, the half towards its vertex; the discriminant from the
            // ray's distance to the centre (r^2 - |l|^2), which keeps its precision in float.
            vec3 centre = vec3(0.0, 0.0, s.y + s.x);
            vec3 oc = o - centre;
            float b = dot(oc, d);
            vec3 l = oc - b * d;
            float disc = s.x * s.x - dot(l, l);
            if (disc < 0.0) return false;
            float root = sqrt(disc);
            float t = -b - root;
            if (t <= 0.0 || (o.z + t * d.z - centre.z) * s.x > 0.0) t = -b + root;
            if (t <= 0.0 || (o.z + t * d.z - centre.z) * s.x > 0.0) return false;
            p = o + t * d;
            n = (p - centre) / abs(s.x);
        }
        if (s.w > 0.0) {
            pass = lensStopTransmission(p.xy);
            if (pass <= 0.0) return false;
        } else if (dot(p.xy, p.xy) > s.z * s.z) {
            return false;
        }
        float n1 = lensSurfaces[2u * k + 1u][channel];
        float n2 = k > 0u ? lensSurfaces[2u * k - 1u][channel] : 1.0;
        if (n1 != n2) {
            if (dot(n, d) > 0.0) n = -n;
            vec3 r = refract(d, n, n1 / n2);
            if (r == vec3(0.0)) return false;  // total internal reflection
            d = normalize(r);
        }
        o = p;
    }
    return true;
}

// The ray in the lens's frame from film point `film` (mm) through pupil sample u at the line of
// `channel` (0, 1, 2: C, d, F), and its weight; false where the lens blocks it.
bool lensRayFromFilm(vec2 film, vec2 u, uint channel, out vec3 o, out vec3 d, out float weight) {
    weight = 0.0;
    float r = length(film);
    int bin = min(int(r / lensInfo.z * float(LENS_PUPIL_BINS)), LENS_PUPIL_BINS - 1);
    vec4 b = lensPupil[bin];
    o = vec3(film, lensInfo.y);
    d = vec3(0.0, 0.0, -1.0);
    if (b.x > b.z) return false;
    vec2 q = mix(b.xy, b.zw, u);
    vec2 dir = r > 0.0 ? film / r : vec2(1.0, 0.0);
    vec2 rear = vec2(q.x * dir.x - q.y * dir.y, q.x * dir.y + q.y * dir.x);
    d = normalize(vec3(rear, lensFilm.z) - o);
    float cosTheta = abs(d.z);
    float pass;
    if (!lensTrace(o, d, channel, pass)) return false;
    float dz = lensInfo.y - lensFilm.z;
    float c2 = cosTheta * cosTheta;
    weight = pass * c2 * c2 * (b.z - b.x) * (b.w - b.y) / (dz * dz) * lensInfo.w;
    return true;
}

// The camera ray through image position ndc ([-1, 1]^2, +y up) and its weight per channel.
Ray lensCameraRay(vec2 ndc, vec2 u, out vec3 weight) {
    uint channel = 1u;
    vec3 mask = vec3(1.0);
    if (lensStop.z > 0.0) {
        float c = min(floor(u.x * 3.0), 2.0);
        u.x = u.x * 3.0 - c;
        channel = uint(c);
        mask = vec3(0.0);
        mask[channel] = 3.0;
    }
    // The lens turns the image over: the image's +x is the film's -x.
    vec3 o, d;
    float w;
    bool passes = lensRayFromFilm(-ndc * lensFilm.xy, u, channel, o, d, w);
    weight = passes ? w * mask : vec3(0.0);
    vec3 right = normalize(frame.camRight.xyz), up = normalize(frame.camUp.xyz), forward = frame.camForward.xyz;
    Ray ray;
    ray.o = frame.camPosition.xyz + lensStop.w * (o.x * right + o.y * up + (lensInfo.y - o.z) * forward);
    ray.d = normalize(d.x * right + d.y * up - d.z * forward);
    return ray;
}

#endif
