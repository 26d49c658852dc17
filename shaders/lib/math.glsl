// Constants and small helpers used everywhere.
#ifndef LIB_MATH_GLSL
#define LIB_MATH_GLSL

const float PI = 3.14159265358979323846;
const float INV_PI = 0.31830988618379067154;
const float INV_4PI = 0.07957747154594766788;
const float FLT_MAX = 3.402823466e38;

// Rec. 709 / sRGB luminance weights (ITU-R BT.709).
float luminance(vec3 c) { return dot(c, vec3(0.2126, 0.7152, 0.0722)); }
float maxComponent(vec3 v) { return max(v.x, max(v.y, v.z)); }
// normalize() of a vector whose squared length underflows a float (a cross product of two edges
// ~1e-11 long is ~1e-22, its square 1e-44, flushed to 0 by GPUs and llvmpipe: the normal came out
// NaN or 0 and the Cornell box scaled by 1e-11 rendered black): scaled by its largest component
// first. A zero vector stays zero.
vec3 normalizeScaled(vec3 v) {
    float m = maxComponent(abs(v));
    return m > 0.0 ? normalize(v * (1.0 / m)) : v;
}
float safeSqrt(float x) { return sqrt(max(x, 0.0)); }
float sqr(float x) { return x * x; }

// Orthonormal basis around a unit vector n (Duff et al. 2017, "Building an Orthonormal Basis,
// Revisited", JCGT 6(1), listing 3): continuous except at the sign flip, no normalisation.
void buildOnb(vec3 n, out vec3 t, out vec3 b) {
    float s = n.z >= 0.0 ? 1.0 : -1.0;
    float a = -1.0 / (s + n.z);
    float c = n.x * n.y * a;
    t = vec3(1.0 + s * n.x * n.x * a, s * c, -s * n.x);
    b = vec3(c, s + n.y * n.y * a, -n.y);
}

struct Frame { vec3 t; vec3 b; vec3 n; };
Frame frameFromNormal(vec3 n) { Frame f; f.n = n; buildOnb(n, f.t, f.b); return f; }
vec3 toLocal(Frame f, vec3 v) { return vec3(dot(v, f.t), dot(v, f.b), dot(v, f.n)); }
vec3 toWorld(Frame f, vec3 v) { return f.t * v.x + f.b * v.y + f.n * v.z; }

#endif
