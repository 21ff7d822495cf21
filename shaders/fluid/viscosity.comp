#version 430
// Stage viscosity: vorticity confinement f = eps (N x omega), N = grad|omega| / |grad|omega||
// where |omega| varies at the kernel's scale (confinement_dv, pbf_kernels.h),
// and XSPH viscosity v += c sum_j (m / rho_j) (v_j - v_i) W_ij. Writes vel_out. Walking the
// list over the step's final positions anyway, it also sums their density (fluid and the
// walls' images: what metrics.comp would sum again) into lambda_rho[i].y, free after the
// velocity pass; the metrics pass then reads it instead of walking the list a second time.
#define USE_POS
#define USE_VEL
#define USE_VEL_OUT
#define WRITE_VEL_OUT
#define USE_NB
#define USE_OMEGA
#define USE_LAMBDA
#define WRITE_LAMBDA
#include "common.glsl"
layout(local_size_x = PBF_WG) in;

void main()
{
    uint i = gl_GlobalInvocationID.x;
    if (i >= particle_count()) return;
    vec3 xi = pos[i].xyz;
    vec3 vi = vel[i].xyz;
    vec3 xsph = vec3(0.0);
    uint nn = nb_len(i);
    vec3 v = vi;
    float sum_w = w_spiky(0.0);
    if (P.vorticity > 0.0) {
        // omega was computed by the vorticity pass (which only runs when vorticity > 0).
        float wi = omega[i].w;
        vec3 eta = vec3(0.0);
        for (uint q = 0u; q < nn; q++) {
            uint j = nb_at(i, q);
            vec3 r = xi - pos[j].xyz;
            vec4 vj = vel[j]; // w: volume m / rho_j (velocity pass)
            eta += vj.w * (omega[j].w - wi) * grad_spiky(r);
            xsph += vj.w * (vj.xyz - vi) * w_poly6(dot(r, r));
            sum_w += w_spiky(length(r));
        }
        v += confinement_dv(eta, omega[i].xyz, wi);
    } else {
        // Four neighbours per trip, loads first (as density.comp and delta.comp); the sums
        // still in list order.
        uint q = 0u;
        for (; q + 3u < nn; q += 4u) {
            uint ja = nb_at(i, q), jb = nb_at(i, q + 1u), jc = nb_at(i, q + 2u), jd = nb_at(i, q + 3u);
            vec3 ra = xi - pos[ja].xyz, rb = xi - pos[jb].xyz, rc = xi - pos[jc].xyz, rd = xi - pos[jd].xyz;
            vec4 va = vel[ja], vb = vel[jb], vc = vel[jc], vd = vel[jd];
            xsph += va.w * (va.xyz - vi) * w_poly6(dot(ra, ra));
            sum_w += w_spiky(length(ra));
            xsph += vb.w * (vb.xyz - vi) * w_poly6(dot(rb, rb));
            sum_w += w_spiky(length(rb));
            xsph += vc.w * (vc.xyz - vi) * w_poly6(dot(rc, rc));
            sum_w += w_spiky(length(rc));
            xsph += vd.w * (vd.xyz - vi) * w_poly6(dot(rd, rd));
            sum_w += w_spiky(length(rd));
        }
        for (; q < nn; q++) { // the last 0-3
            uint j = nb_at(i, q);
            vec3 r = xi - pos[j].xyz;
            vec4 vj = vel[j];
            xsph += vj.w * (vj.xyz - vi) * w_poly6(dot(r, r));
            sum_w += w_spiky(length(r));
        }
    }
    add_final_wall_images(i, xi, nn, sum_w);
    lambda_rho[i].y = P.mass_density * sum_w; // the final positions' density, bodies' share aside
    v += P.viscosity * xsph;
    vel_out[i] = vec4(v, vel[i].w);
}
