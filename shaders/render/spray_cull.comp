#version 430 core
// Finds the spray before it is drawn, so that the spray pass draws those particles only
// (an indirect draw of spray_command over spray_list) instead of sending every particle
// through the raster pipeline to drop all but a few. Spray: particles.vert's test (SPRAY),
// at least u_spray_speed and at most u_spray_density rho0. The list's order is the same in
// every run (the drops are blended over each other in that order):
//   CULL_COUNT   each work group counts its spray (the same grid-stride loop as CULL_WRITE)
//   CULL_SCAN    one work group: each group's offset, and the command {4, total, 0, 0}
//   CULL_WRITE   each group writes its spray (index, and the drop's opacity factor v_alpha
//                as particles.vert gives it) from its offset, in loop order
#include "render_shared.glsl"

#ifdef CULL_SCAN
layout(local_size_x = 1024) in;
#else
layout(local_size_x = 64) in;
#endif

layout(std430, binding = ENG_RENDER_SPRAY_GROUPS_BINDING) buffer Groups {
    uint group_count[]; // per work group of CULL_COUNT; CULL_SCAN turns them into offsets
};

uniform uint u_groups; // work groups of CULL_COUNT and CULL_WRITE

#ifdef CULL_SCAN
layout(std430, binding = ENG_RENDER_SPRAY_CMD_BINDING) writeonly buffer SprayDraw {
    uint spray_command[4]; // DrawArraysIndirectCommand
};
shared uint partial[1024];

void main()
{
    // Each invocation sums a contiguous run of groups, the runs are scanned, then each
    // run's offsets are written.
    uint lane = gl_LocalInvocationID.x;
    uint per = (u_groups + 1023u) / 1024u, first = lane * per, last = min(first + per, u_groups);
    uint sum = 0u;
    for (uint g = first; g < last; g++) sum += group_count[g];
    partial[lane] = sum;
    barrier();
    for (uint step = 1u; step < 1024u; step <<= 1) { // inclusive scan (Hillis-Steele)
        uint add = lane >= step ? partial[lane - step] : 0u;
        barrier();
        partial[lane] += add;
        barrier();
    }
    uint offset = partial[lane] - sum;
    for (uint g = first; g < last; g++) {
        uint c = group_count[g];
        group_count[g] = offset;
        offset += c;
    }
    if (lane == 1023u) {
        spray_command[0] = 4u;
        spray_command[1] = partial[1023];
        spray_command[2] = 0u;
        spray_command[3] = 0u;
    }
}
#else
layout(std430, binding = ENG_RENDER_VELOCITY_SSBO_BINDING) readonly buffer Velocities {
    vec4 velocities[]; // xyz: m/s, w: the particle's volume m^3
};
layout(std430, binding = ENG_RENDER_DRAW_SSBO_BINDING) readonly buffer Draw {
    uint draw_command[4];
};
uniform int u_count;
uniform float u_spray_speed;
uniform float u_spray_density;
uniform float u_particle_mass;
uniform float u_inv_rest_density;

bool is_spray(uint i, out float alpha)
{
    vec4 vel = velocities[i];
    float speed = length(vel.xyz);
    float ratio = vel.w > 0.0 ? u_particle_mass / vel.w * u_inv_rest_density : 1.0;
    alpha = clamp((speed - u_spray_speed) / u_spray_speed, 0.0, 1.0);
    return !(speed < u_spray_speed || ratio > u_spray_density);
}

#ifdef CULL_COUNT
shared uint found;
void main()
{
    if (gl_LocalInvocationID.x == 0u) found = 0u;
    barrier();
    uint n = min(draw_command[1], uint(max(u_count, 0))), stride = u_groups * 64u;
    uint mine = 0u;
    float alpha;
    for (uint i = gl_GlobalInvocationID.x; i < n; i += stride) mine += is_spray(i, alpha) ? 1u : 0u;
    if (mine > 0u) atomicAdd(found, mine);
    barrier();
    if (gl_LocalInvocationID.x == 0u) group_count[gl_WorkGroupID.x] = found;
}
#endif

#ifdef CULL_WRITE
layout(std430, binding = ENG_RENDER_SPRAY_CMD_BINDING) readonly buffer SprayDraw {
    uint spray_command[4];
};
layout(std430, binding = ENG_RENDER_SPRAY_LIST_BINDING) writeonly buffer SprayList {
    uvec2 spray_list[]; // particle index, floatBitsToUint(v_alpha)
};
shared uint flags[64];
void main()
{
    uint lane = gl_LocalInvocationID.x;
    uint n = min(draw_command[1], uint(max(u_count, 0))), stride = u_groups * 64u;
    uint g = gl_WorkGroupID.x, next = group_count[g];
    // A group without spray (most of them) has nothing to write.
    if ((g + 1u < u_groups ? group_count[g + 1u] : spray_command[1]) == next) return;
    // Every lane takes the same number of trips, so the barriers are uniform.
    for (uint base = gl_WorkGroupID.x * 64u; base < n; base += stride) {
        uint i = base + lane;
        float alpha = 0.0;
        bool spray = i < n && is_spray(i, alpha);
        flags[lane] = spray ? 1u : 0u;
        barrier();
        uint before = 0u, all = 0u;
        for (uint k = 0u; k < 64u; k++) {
            before += k < lane ? flags[k] : 0u;
            all += flags[k];
        }
        if (spray) spray_list[next + before] = uvec2(i, floatBitsToUint(alpha));
        next += all;
        barrier();
    }
}
#endif
#endif
