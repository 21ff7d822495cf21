#version 430
// Stage density (iterations after the first; neighbours.comp does the first): rho_i from
// the fluid neighbours (spiky) plus the boundaries' share, the constraint
// C_i = max(rho_i / rho0 - 1, 0) and its multiplier lambda_i = -C_i / (sum |grad C|^2 + eps).
#define USE_PRED
#define WRITE_PRED
#define USE_NB
#define USE_LAMBDA
#define WRITE_LAMBDA
#define USE_COLLIDERS
#include "common.glsl"
#include "colliders.glsl"
#include "density.glsl"
layout(local_size_x = PBF_WG) in;

void main()
{
    uint i = gl_GlobalInvocationID.x;
    if (i >= particle_count()) return;
    vec3 xi = pred[i].xyz;
    float sum_w = w_spiky(0.0);
    vec3 grad_i = vec3(0.0);
    float sum_grad2 = 0.0;
    uint nn = nb_len(i);
    vec3 twice;
    uint mask = mirror_mask(xi, twice);
    uint q = 0u;
    for (; q + 3u < nn; q += 4u) { // four per trip, loads first; sums still in list order
        uint ja = nb_at(i, q), jb = nb_at(i, q + 1u), jc = nb_at(i, q + 2u), jd = nb_at(i, q + 3u);
        vec3 ra = xi - pred[ja].xyz;
        vec3 rb = xi - pred[jb].xyz;
        vec3 rc = xi - pred[jc].xyz;
        vec3 rd = xi - pred[jd].xyz;
        density_add(ra, sum_w, grad_i, sum_grad2);
        density_add(rb, sum_w, grad_i, sum_grad2);
        density_add(rc, sum_w, grad_i, sum_grad2);
        density_add(rd, sum_w, grad_i, sum_grad2);
    }
    for (; q < nn; q++) density_add(xi - pred[nb_at(i, q)].xyz, sum_w, grad_i, sum_grad2); // the last 0-3
    if (mask != 0u) { // next to a wall: the neighbours' images
        for (q = 0u; q < nn; q++) density_add_images(xi, pred[nb_at(i, q)].xyz, mask, twice, sum_w, grad_i, sum_grad2);
    }
    density_finish(i, xi, mask, twice, sum_w, grad_i, sum_grad2);
}
