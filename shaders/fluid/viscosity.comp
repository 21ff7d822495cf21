#version 430
// Stage viscosity: vorticity confinement f = eps (N x omega), N = grad|omega| / |grad|omega||,
// and XSPH viscosity v += c sum_j (m / rho_j) (v_j - v_i) W_ij. Writes vel_out.
#define USE_POS
#define USE_VEL
#define USE_VEL_OUT
#define USE_NB
#define USE_LAMBDA
#define USE_OMEGA
#include "common.glsl"
layout(local_size_x = PBF_WG) in;

void main()
{
    uint i = gl_GlobalInvocationID.x;
    if (i >= P.count) return;
    vec3 xi = pos[i].xyz;
    vec3 vi = vel[i].xyz;
    float wi = omega[i].w;
    vec3 eta = vec3(0.0);
    vec3 xsph = vec3(0.0);
    uint nn = nb_len(i);
    for (uint q = 0u; q < nn; q++) {
        uint j = nb_at(i, q);
        vec3 r = xi - pos[j].xyz;
        float vol = P.mass_density / max(lambda_rho[j].y, 1e-6 * P.rest_density);
        eta += vol * (omega[j].w - wi) * grad_spiky(r);
        xsph += vol * (vel[j].xyz - vi) * w_poly6(dot(r, r));
    }
    vec3 v = vi + P.viscosity * xsph;
    float le = length(eta);
    if (P.vorticity > 0.0 && le > 1e-9)
        v += P.dt * P.vorticity * cross(eta / le, omega[i].xyz);
    vel_out[i] = vec4(v, vel[i].w);
}
