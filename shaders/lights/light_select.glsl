// Which light next event estimation samples, and the exact probability of that choice (MIS needs
// it again when a BSDF-sampled ray hits an emitter). frame.sampling.y chooses the rule:
//
// LIGHT_SELECT_TREE (default): the environment against the light tree, then down the tree
//   (renderer/light_tree.h builds it), each step choosing a child in proportion to its importance
//   at the shading point (Conty Estevez and Kulla 2018, "Importance Sampling of Many Lights with
//   Adaptive Tree Splitting", sec. 4; pbrt-v4's BVHLightSampler is the same idea):
//     importance = intensity * cos(theta') * cos(theta_i') / max(d^2, r^2)
//   with d the distance from the shading point to the centre of the node's box, r the radius of
//   the box's bounding sphere, theta_u the half-angle that sphere subtends (pi inside it),
//   theta' = max(0, theta - theta_o - theta_u) the angle between the emitters' cone and the
//   direction to the point (0 when theta' >= theta_e), and theta_i' = max(0, theta_i - theta_u) the
//   angle at the receiver between its normal and the node (|cos| for receivers that transmit; a
//   node wholly below a reflecting receiver's horizon gets 0, as its lights contribute nothing
//   there). Its unit is irradiance (W m^-2), so the environment, whose irradiance on a surface is
//   pi * its mean luminance (frame.envSelect.x), is chosen with probability
//   E_env / (E_env + importance of the tree's top two nodes).
//   The pmf of light i is recomputed by walking its path (GpuLight::tree.x, one bit per level)
//   with the same function, so sampling and pmf agree exactly.
// LIGHT_SELECT_POWER / LIGHT_SELECT_UNIFORM: one global CDF (GpuLight::color.w, lightCdf).
#ifndef LIGHTS_LIGHT_SELECT_GLSL
#define LIGHTS_LIGHT_SELECT_GLSL
#include "../scene/buffers.glsl"
#include "../lib/math.glsl"

layout(std430, binding = BINDING_LIGHT_TREE) readonly buffer LightTreeBuffer { GpuLightNode lightTree[]; };

#define GPU_TEXELS lightNodeTexels
GPU_TEXEL_LOADER(GpuLightNode, GPU_LIGHT_NODE_ROWS, loadLightNode, lightTree)
#undef GPU_TEXELS

const float ONE_MINUS_EPSILON = 0.99999994;  // the largest float below 1

// cos(max(0, a - b)) and sin(max(0, a - b)) from the sines and cosines of angles a, b in [0, pi].
float cosSubClamped(float sinA, float cosA, float sinB, float cosB) {
    return cosA > cosB ? 1.0 : cosA * cosB + sinA * sinB;
}
float sinSubClamped(float sinA, float cosA, float sinB, float cosB) {
    return cosA > cosB ? 0.0 : sinA * cosB - cosA * sinB;
}

// The importance of tree node `i` for the point p with normal n (see the header).
float lightNodeImportance(uint i, vec3 p, vec3 n, bool twoSided) {
    GpuLightNode node = loadLightNode(i);
    float intensity = node.boundsMin.w;
    if (!(intensity > 0.0)) return 0.0;
    vec3 c = 0.5 * (node.boundsMin.xyz + node.boundsMax.xyz);
    vec3 ext = 0.5 * (node.boundsMax.xyz - node.boundsMin.xyz);
    float r2 = dot(ext, ext);
    vec3 toP = p - c;
    float d2 = dot(toP, toP);
    float cosU = -1.0, sinU = 0.0;  // inside the bounding sphere every direction is possible
    if (d2 > r2) {
        float sin2 = r2 / d2;
        sinU = sqrt(sin2);
        cosU = safeSqrt(1.0 - sin2);
    }
    vec3 w = d2 > 0.0 ? toP * inversesqrt(d2) : vec3(0.0, 0.0, 1.0);  // from the node to p
    // Emitter side: theta' = max(0, theta - theta_o - theta_u).
    float cosW = clamp(dot(node.axis.xyz, w), -1.0, 1.0), sinW = safeSqrt(1.0 - cosW * cosW);
    float cosO = node.boundsMax.w, sinO = safeSqrt(1.0 - cosO * cosO);
    float cosX = cosSubClamped(sinW, cosW, sinO, cosO), sinX = sinSubClamped(sinW, cosW, sinO, cosO);
    float cosP = cosSubClamped(sinX, cosX, sinU, cosU);
    if (cosP <= node.axis.w) return 0.0;
    // Receiver side: theta_i' = max(0, theta_i - theta_u).
    float cosI = -dot(n, w);
    if (twoSided) cosI = abs(cosI);
    cosI = clamp(cosI, -1.0, 1.0);
    float sinI = safeSqrt(1.0 - cosI * cosI);
    float cosIP = cosSubClamped(sinI, cosI, sinU, cosU);
    // A medium vertex (a zero normal; integrator/medium.glsl) receives from every direction.
    if (HAS_MEDIA(MEDIA_SCATTERING) && n == vec3(0.0)) cosIP = 1.0;
    if (cosIP <= 0.0) return 0.0;
    return intensity * cosP * cosIP / max(d2, r2);
}

// Probability of choosing the environment (when there is one) at p.
float envSelectProbability(vec3 p, vec3 n, bool twoSided) {
    if (frame.dispatch.y == 0u) return 0.0;
    uint nodes = frame.sampling.w;
    if (nodes == 0u) return 1.0;
    float local = lightNodeImportance(0u, p, n, twoSided);
    uint right = loadLightNode(0u).info.x;
    if (nodes > 1u && (right & LIGHT_TREE_LEAF) == 0u)
        local = lightNodeImportance(1u, p, n, twoSided) + lightNodeImportance(right, p, n, twoSided);
    float env = frame.envSelect.x;
    return env + local > 0.0 ? env / (env + local) : 0.0;
}

// Chooses a light for next event estimation at p (normal n; twoSided: the material transmits).
// False when no light can contribute there; else `light` and its selection probability `pmf`.
// Whether selection reads the global CDF (power, uniform) rather than the tree; a
// scene-specialised program keeps only the rule it renders with (scene/features.glsl).
bool lightSelectionByCdf() {
    if (!HAS_LIGHT_SELECTION(LIGHT_SELECT_TREE)) return true;
    if (ONLY_KIND(CAUSTIC_LIGHT_SELECTIONS, LIGHT_SELECT_TREE)) return false;
    return frame.sampling.y != LIGHT_SELECT_TREE;
}

bool selectLight(float u, vec3 p, vec3 n, bool twoSided, out uint light, out float pmf) {
    light = 0u;
    pmf = 0.0;
    uint count = frame.counts.y;
    if (count == 0u) return false;
    // One light (the environment counts): every rule picks it with probability 1.
    if (CAUSTIC_SINGLE_LIGHT != 0u) { pmf = 1.0; return true; }
    if (lightSelectionByCdf()) {
        uint lo = 0u, hi = count - 1u;  // invert the CDF (binary search)
        while (lo < hi) {
            uint mid = (lo + hi) >> 1;
            if (u < lightCdf(mid)) hi = mid; else lo = mid + 1u;
        }
        light = lo;
        pmf = loadLight(lo).color.w;
        return pmf > 0.0;
    }
    float pEnv = envSelectProbability(p, n, twoSided);
    if (u < pEnv) {
        light = frame.dispatch.y - 1u;
        pmf = pEnv;
        return true;
    }
    if (frame.sampling.w == 0u) return false;
    u = min((u - pEnv) / (1.0 - pEnv), ONE_MINUS_EPSILON);
    pmf = 1.0 - pEnv;
    uint node = 0u;
    for (uint depth = 0u; depth < 32u; ++depth) {
        uint right = loadLightNode(node).info.x;
        if ((right & LIGHT_TREE_LEAF) != 0u) {
            light = right & ~LIGHT_TREE_LEAF;
            return pmf > 0.0;
        }
        float il = lightNodeImportance(node + 1u, p, n, twoSided);
        float ir = lightNodeImportance(right, p, n, twoSided);
        if (!(il + ir > 0.0)) return false;
        float pl = il / (il + ir);
        if (u < pl) {
            u = min(u / pl, ONE_MINUS_EPSILON);
            pmf *= pl;
            node = node + 1u;
        } else {
            u = min((u - pl) / (1.0 - pl), ONE_MINUS_EPSILON);
            pmf *= 1.0 - pl;
            node = right;
        }
    }
    return false;
}

// The probability that selectLight(., p, n, twoSided) chooses `light`.
float lightSelectPmf(uint light, vec3 p, vec3 n, bool twoSided) {
    if (CAUSTIC_SINGLE_LIGHT != 0u) return 1.0;
    if (lightSelectionByCdf()) return loadLight(light).color.w;
    float pEnv = envSelectProbability(p, n, twoSided);
    if (light + 1u == frame.dispatch.y) return pEnv;
    float pmf = 1.0 - pEnv;
    uint trail = loadLight(light).tree.x;
    uint node = 0u;
    for (uint depth = 0u; depth < 32u; ++depth) {
        uint right = loadLightNode(node).info.x;
        if ((right & LIGHT_TREE_LEAF) != 0u) return (right & ~LIGHT_TREE_LEAF) == light ? pmf : 0.0;
        float il = lightNodeImportance(node + 1u, p, n, twoSided);
        float ir = lightNodeImportance(right, p, n, twoSided);
        if (!(il + ir > 0.0)) return 0.0;
        bool goRight = ((trail >> depth) & 1u) != 0u;
        pmf *= goRight ? ir / (il + ir) : il / (il + ir);
        node = goRight ? right : node + 1u;
    }
    return 0.0;
}

#endif
