#version 430
// Stage density: rho_i from fluid neighbours (poly6) plus the boundaries' share, the
// constraint C_i = max(rho_i / rho0 - 1, 0) and its multiplier
// lambda_i = -C_i / (sum_k |grad_k C_i|^2 + epsilon).
#define USE_PRED
#define USE_NB
#define USE_LAMBDA
#define USE_COLLIDERS
#include "common.glsl"
#include "colliders.glsl"
layout(local_size_x = PBF_WG) in;

void main()
{
    uint i = gl_GlobalInvocationID.x;
    if (i >= particle_count()) return;
    vec3 xi = pred[i].xyz;
    float sum_w = w_poly6(0.0);
    vec3 grad_i = vec3(0.0);
    float sum_grad2 = 0.0;
    float k = P.mass_density * P.inv_rest_density;
    uint nn = nb_len(i);
    for (uint q = 0u; q < nn; q++) {
        vec3 r = xi - pred[nb_at(i, q)].xyz;
        float r2 = dot(r, r);
        sum_w += w_poly6(r2);
        vec3 g = k * grad_spiky(r);
        grad_i += g;
        sum_grad2 += dot(g, g);
    }
    float rho = P.mass_density * sum_w;
    vec3 wall_grad;
    rho += P.rest_density * container_boundary(xi, wall_grad);
    grad_i += wall_grad;
    if (P.collider_count > 0u) colliders_density(xi, rho, grad_i);
    float C = max(rho * P.inv_rest_density - 1.0, 0.0);
    float lambda = -C / (dot(grad_i, grad_i) + sum_grad2 + P.epsilon);
    lambda_rho[i] = vec2(lambda, rho);
    // lambda also rides in pred.w, so the delta pass reads a neighbour's position and
    // multiplier in one load (other threads only read pred[j].xyz here).
    pred[i].w = lambda;
}
