#version 450 core
// Test kernel for light selection (lights/light_select.glsl) at the point u_point with normal
// u_normal (u_twoSided: a transmitting receiver):
//   u_mode 0: results[i].x = lightSelectPmf(i) for every light i < u_count;
//   u_mode 1: sample i of u_count chooses a light with u = (i + jitter) / u_count (stratified):
//             results[i] = (light index, or -1 if none, the pmf selectLight returned,
//                           lightSelectPmf of that light).
#include "lights/light_select.glsl"
#include "lib/rng.glsl"

layout(local_size_x = 64) in;
layout(std430, binding = BINDING_TEST_OUTPUT) buffer Results { vec4 results[]; };
uniform uint u_mode;
uniform uint u_count;
uniform vec3 u_point;
uniform vec3 u_normal;
uniform uint u_twoSided;

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= u_count) return;
    bool twoSided = u_twoSided != 0u;
    if (u_mode == 0u) {
        results[i] = vec4(lightSelectPmf(i, u_point, u_normal, twoSided), 0.0, 0.0, 0.0);
        return;
    }
    uint rng = rngInit(i, 0u, 4242u);
    float u = (float(i) + rngNext(rng)) / float(u_count);
    uint light;
    float pmf;
    if (selectLight(u, u_point, u_normal, twoSided, light, pmf))
        results[i] = vec4(float(light), pmf, lightSelectPmf(light, u_point, u_normal, twoSided), 0.0);
    else
        results[i] = vec4(-1.0, 0.0, 0.0, 0.0);
}
