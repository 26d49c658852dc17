// The environment: what a ray that leaves the scene sees, and what the environment light emits.
// One lookup serves both, so escaped rays and light samples always agree.
//   constant: a uniform radiance.
//   sky:      a gradient from the horizon radiance (at and below the horizon) to the zenith
//             radiance straight up, blended with sqrt(max(y, 0)) so that the bright horizon band is
//             wider than a linear blend would make it. +y is up.
#ifndef LIGHTS_ENVIRONMENT_GLSL
#define LIGHTS_ENVIRONMENT_GLSL
#include "../scene/buffers.glsl"

vec3 environmentRadiance(vec3 dir) {
    uint type = frame.envInfo.x;
    if (type == ENV_CONSTANT) return frame.envRadiance.rgb;
    if (type == ENV_SKY) {
        float t = sqrt(clamp(dir.y, 0.0, 1.0));
        return mix(frame.envHorizon.rgb, frame.envZenith.rgb, t);
    }
    return vec3(0.0);
}

#endif
