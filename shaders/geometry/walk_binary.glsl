// A mesh's own BVH in its binary form (GpuBvhNode, renderer/bvh.h), walked with the pending
// nodes on the memory stack: NVIDIA's walk (renderer/integrator_config.h chooses it), and the one
// for any configuration without the 4-wide tree. Reads the nodes through loadBvhNode (storage
// buffers, or buffer textures with CAUSTIC_FETCH_TEXELS).
// Included by geometry/bvh.glsl, which declares what it uses (bvhDescend, traceLeafTriangles,
// g_bvhStack, WALK_STATS_*).
#ifndef GEOMETRY_WALK_BINARY_GLSL
#define GEOMETRY_WALK_BINARY_GLSL

// The instance's tree below its root, whose box the ray (o, d in object space) is known to hit,
// on the stack above `base`, which it leaves as it found it.
bool traceInstanceTree(GpuInstance inst, uint instance, vec3 o, vec3 d, vec3 invD, bool anyHit, int base,
                       inout TraceHit hit) {
    WALK_STATS_TREE()
    WatertightRay wr = makeWatertightRay(o, d);
    uint node = inst.rootNode;
    uint firstTriangle = inst.firstTriangle;
    int sp = base;
    bool found = false;
    GpuBvhNode n = loadBvhNode(node);
    while (true) {
        WALK_STATS_STEP()
        uint count = n.countAndAxis >> 2;
        if (count == 0u) {
            if (bvhDescend(n, node, o, invD, hit.t, sp)) continue;
        } else if (traceLeafTriangles(wr, inst, instance, firstTriangle, n.rightOrFirst, count, anyHit, hit)) {
            found = true;
            if (anyHit) return true;
        }
        if (sp == base) break;
        node = g_bvhStack[--sp];
        n = loadBvhNode(node);
    }
    return found;
}

#endif
