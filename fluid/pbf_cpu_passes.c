// CPU reference, the passes: each function mirrors one shader of shaders/fluid/ (named in
// its comment), per particle in slot order, in the shader's order of operations.
#include "fluid/pbf_cpu_internal.h"

#include <string.h>

// ---- kernels and boundaries (common.glsl, colliders.glsl) -----------------------------

float pbf_cpu_poly6(const pbf_gpu_params *P, float r2)
{
    float d = P->h * P->h - r2;
    return d > 0.0f ? P->poly6 * d * d * d : 0.0f;
}

/// Gradient of the spiky kernel with respect to x_i for r = x_i - x_j (1/m^4).
v3 pbf_cpu_grad_spiky(const pbf_gpu_params *P, v3 r)
{
    float len = length(r);
    if (len <= 1e-9f * P->h || len >= P->h) return (v3){ 0.0f, 0.0f, 0.0f };
    float d = P->h - len;
    return scale(P->spiky_grad * d * d / len, r);
}

float pbf_cpu_boundary_volume(float d, float h)
{
    float u = clampf(d / h, 0.0f, 1.0f);
    float u2 = u * u;
    // F(u) = u - 4u^3/3 + 6u^5/5 - 4u^7/7 + u^9/9, the antiderivative of (1 - u^2)^4.
    float F = u * (1.0f + u2 * (-4.0f / 3.0f + u2 * (6.0f / 5.0f + u2 * (-4.0f / 7.0f + u2 / 9.0f))));
    return (315.0f / 256.0f) * (128.0f / 315.0f - F);
}

float pbf_cpu_boundary_gradient(float d, float h)
{
    float u = clampf(d / h, 0.0f, 1.0f);
    // H(u) = u^2/2 - u^3 + 3u^4/4 - u^5/5, the antiderivative of u (1 - u)^3.
    float H = u * u * (0.5f + u * (-1.0f + u * (0.75f - u * 0.2f)));
    return (30.0f / h) * (0.05f - H);
}

/// common.glsl boundary_volume with the lattice calibration, in the shader's order of
/// operations (pbf_cpu_boundary_volume is the continuous V(d) the tests integrate).
float pbf_cpu_wall_volume(const pbf_gpu_params *P, float d)
{
    float u = clampf(d / P->h, 0.0f, 1.0f);
    float u2 = u * u;
    float F = u * (1.0f + u2 * (-4.0f / 3.0f + u2 * (6.0f / 5.0f + u2 * (-4.0f / 7.0f + u2 / 9.0f))));
    return P->boundary_scale * (315.0f / 256.0f) * (128.0f / 315.0f - F);
}

/// common.glsl boundary_gradient, likewise (1/m).
float pbf_cpu_wall_gradient(const pbf_gpu_params *P, float d)
{
    float u = clampf(d / P->h, 0.0f, 1.0f);
    float H = u * u * (0.5f + u * (-1.0f + u * (0.75f - u * 0.2f)));
    return P->boundary_scale * (30.0f / P->h) * (0.05f - H);
}

static float plane_distance(const pbf_gpu_params *P, uint32_t p, v3 x, v3 *n)
{
    *n = xyz(P->planes[p]);
    return dot(x, *n) - P->planes[p].w;
}

/// common.glsl container_boundary: the union of the planes' half-spaces.
float pbf_cpu_container_boundary(const pbf_gpu_params *P, v3 x, v3 *grad)
{
    float keep = 1.0f;
    float vp[PBF_MAX_PLANES];
    v3 gp[PBF_MAX_PLANES];
    for (uint32_t p = 0; p < P->plane_count; p++) {
        v3 n;
        float d = plane_distance(P, p, x, &n);
        vp[p] = d < P->h ? pbf_cpu_wall_volume(P, d) : 0.0f;
        gp[p] = d < P->h ? scale(pbf_cpu_wall_gradient(P, d), n) : (v3){ 0.0f, 0.0f, 0.0f };
        keep *= 1.0f - vp[p];
    }
    *grad = (v3){ 0.0f, 0.0f, 0.0f };
    for (uint32_t p = 0; p < P->plane_count; p++) {
        if (vp[p] <= 0.0f) continue;
        float others = 1.0f;
        for (uint32_t q = 0; q < P->plane_count; q++)
            if (q != p) others *= 1.0f - vp[q];
        *grad = sub(*grad, scale(others, gp[p]));
    }
    return 1.0f - keep;
}

void pbf_cpu_predict(pbf_cpu_world *w, const pbf_gpu_params *P)
{
    for (uint32_t i = 0; i < w->count; i++) {
        v3 v = add(xyz(w->vel[i]), scale(P->dt, xyz(P->gravity)));
        v = scale(1.0f / (1.0f + P->damping * P->dt), v);
        float s = length(v);
        if (s > P->max_speed) v = scale(P->max_speed / s, v);
        w->vel[i] = (pbf_float4){ v.x, v.y, v.z, w->vel[i].w };
        v3 x = add(xyz(w->pos[i]), scale(P->dt, v));
        w->pred[i] = (pbf_float4){ x.x, x.y, x.z, 0.0f };
    }
}

/// Cell of a position along one axis, clamped to the grid (common.glsl's cell_coord).
static int cell_axis(float x, float origin, float inv_cell, uint32_t dim)
{
    float f = floorf((x - origin) * inv_cell);
    if (!(f >= 0.0f)) return 0; // also NaN
    if (f >= (float)(dim - 1)) return (int)dim - 1;
    return (int)f;
}

static void cell_coord(const pbf_gpu_params *P, v3 x, int c[3])
{
    c[0] = cell_axis(x.x, P->grid_origin.x, P->inv_cell, P->grid_dims.x);
    c[1] = cell_axis(x.y, P->grid_origin.y, P->inv_cell, P->grid_dims.y);
    c[2] = cell_axis(x.z, P->grid_origin.z, P->inv_cell, P->grid_dims.z);
}

static uint32_t cell_index(const pbf_gpu_params *P, int x, int y, int z)
{
    return (uint32_t)x + P->grid_dims.x * ((uint32_t)y + P->grid_dims.y * (uint32_t)z);
}

/// grid_count, scan, grid_scatter and grid_sort together: a stable counting sort of the
/// slots by the cell of x. sorted[k] is the slot in place k of cell order.
void pbf_cpu_build_grid(pbf_cpu_world *w, const pbf_float4 *x, const pbf_gpu_params *P)
{
    memset(w->cell_start, 0, ((size_t)w->cells + 1) * 4);
    memset(w->cell_fill, 0, (size_t)w->cells * 4);
    for (uint32_t i = 0; i < w->count; i++) {
        int c[3];
        cell_coord(P, xyz(x[i]), c);
        w->cell_of[i] = cell_index(P, c[0], c[1], c[2]);
        w->cell_start[w->cell_of[i]]++;
    }
    uint32_t sum = 0;
    for (uint32_t c = 0; c <= w->cells; c++) {
        uint32_t n = w->cell_start[c];
        w->cell_start[c] = sum;
        sum += n;
    }
    for (uint32_t i = 0; i < w->count; i++) {
        uint32_t c = w->cell_of[i];
        w->sorted[w->cell_start[c] + w->cell_fill[c]++] = i;
    }
}

void pbf_cpu_swap4(pbf_float4 **a, pbf_float4 **b)
{
    pbf_float4 *t = *a;
    *a = *b;
    *b = t;
}

static void swap_ids(uint32_t **a, uint32_t **b)
{
    uint32_t *t = *a;
    *a = *b;
    *b = t;
}

/// reorder.comp: gathers the particle data into cell order; afterwards slot k is place k.
void pbf_cpu_reorder(pbf_cpu_world *w)
{
    for (uint32_t i = 0; i < w->count; i++) {
        uint32_t j = w->sorted[i];
        w->pos_out[i] = w->pos[j];
        w->vel_out[i] = w->vel[j];
        w->pred_out[i] = w->pred[j];
        w->id_out[i] = w->id[j];
    }
    pbf_cpu_swap4(&w->pos, &w->pos_out);
    pbf_cpu_swap4(&w->vel, &w->vel_out);
    pbf_cpu_swap4(&w->pred, &w->pred_out);
    swap_ids(&w->id, &w->id_out);
    for (uint32_t i = 0; i < w->count; i++) w->sorted[i] = i;
}

/// neighbours.comp: for each slot, the slots within h of x, walked as FOR_NEIGHBOURS walks
/// them (9 runs of 3 cells); a list keeps the first max_neighbours, the count all of them.
void pbf_cpu_find_neighbours(pbf_cpu_world *w, const pbf_float4 *x, const pbf_gpu_params *P)
{
    int dims[3] = { (int)P->grid_dims.x, (int)P->grid_dims.y, (int)P->grid_dims.z };
    float h2 = P->h * P->h;
    for (uint32_t i = 0; i < w->count; i++) {
        v3 xi = xyz(x[i]);
        int c[3];
        cell_coord(P, xi, c);
        uint32_t n = 0, *list = w->nb_list + (size_t)i * w->max_neighbours;
        // The cells within `reach` of the particle's, rows in z then y order, x ascending
        // (neighbours.comp skips rows and trims x ranges that hold nothing within h: the
        // same neighbours in the same order).
        int reach = (int)ceilf(P->h * P->inv_cell - 1e-4f);
        for (int dz = -reach; dz <= reach; dz++)
            for (int dy = -reach; dy <= reach; dy++) {
                int y = c[1] + dy, z = c[2] + dz;
                if (y < 0 || z < 0 || y >= dims[1] || z >= dims[2]) continue;
                int x0 = c[0] - reach > 0 ? c[0] - reach : 0;
                int x1 = c[0] + reach < dims[0] ? c[0] + reach : dims[0] - 1;
                uint32_t b = w->cell_start[cell_index(P, x0, y, z)], e = w->cell_start[cell_index(P, x1, y, z) + 1];
                for (uint32_t k = b; k < e; k++) {
                    uint32_t j = w->sorted[k];
                    v3 r = sub(xi, xyz(x[j]));
                    if (dot(r, r) < h2 && j != i) {
                        if (n < w->max_neighbours) list[n] = j;
                        n++;
                    }
                }
            }
        w->nb_count[i] = n;
    }
}

static uint32_t nb_len(const pbf_cpu_world *w, uint32_t i)
{
    return w->nb_count[i] < w->max_neighbours ? w->nb_count[i] : w->max_neighbours;
}

static const uint32_t *nb_of(const pbf_cpu_world *w, uint32_t i) { return w->nb_list + (size_t)i * w->max_neighbours; }

/// density.comp: rho_i (fluid + boundary share) and lambda_i.
void pbf_cpu_density(pbf_cpu_world *w, const pbf_gpu_params *P)
{
    float k = P->mass_density * P->inv_rest_density;
    for (uint32_t i = 0; i < w->count; i++) {
        v3 xi = xyz(w->pred[i]);
        float sum_w = pbf_cpu_poly6(P, 0.0f);
        v3 grad_i = { 0.0f, 0.0f, 0.0f };
        float sum_grad2 = 0.0f;
        const uint32_t *nb = nb_of(w, i);
        for (uint32_t q = 0, nn = nb_len(w, i); q < nn; q++) {
            v3 r = sub(xi, xyz(w->pred[nb[q]]));
            sum_w += pbf_cpu_poly6(P, dot(r, r));
            v3 g = scale(k, pbf_cpu_grad_spiky(P, r));
            grad_i = add(grad_i, g);
            sum_grad2 += dot(g, g);
        }
        float rho = P->mass_density * sum_w;
        v3 wall_grad;
        rho += P->rest_density * pbf_cpu_container_boundary(P, xi, &wall_grad);
        grad_i = add(grad_i, wall_grad);
        if (P->collider_count > 0u) pbf_cpu_colliders_density(w, P, xi, &rho, &grad_i);
        float C = fmaxf(rho * P->inv_rest_density - 1.0f, 0.0f);
        w->lambda[i] = -C / (dot(grad_i, grad_i) + sum_grad2 + P->epsilon);
        w->rho[i] = rho;
    }
}

/// The collisions both delta.comp and collide.comp end with: a particle radius from every
/// container plane, then the domain clamp, on pred_out[i].
static void container_collide(pbf_cpu_world *w, const pbf_gpu_params *P, uint32_t i)
{
    v3 x = xyz(w->pred_out[i]);
    for (uint32_t p = 0; p < P->plane_count; p++) {
        v3 n;
        float d = plane_distance(P, p, x, &n);
        if (d < P->radius) x = add(x, scale(P->radius - d, n));
    }
    x.x = clampf(x.x, P->domain_min.x + P->radius, P->domain_max.x - P->radius);
    x.y = clampf(x.y, P->domain_min.y + P->radius, P->domain_max.y - P->radius);
    x.z = clampf(x.z, P->domain_min.z + P->radius, P->domain_max.z - P->radius);
    w->pred_out[i] = (pbf_float4){ x.x, x.y, x.z, 0.0f };
}

/// delta.comp: the correction from the fluid and the container, then the container's
/// collisions and the domain clamp, into pred_out.
void pbf_cpu_delta(pbf_cpu_world *w, const pbf_gpu_params *P)
{
    for (uint32_t i = 0; i < w->count; i++) {
        v3 xi = xyz(w->pred[i]);
        float li = w->lambda[i];
        v3 dp = { 0.0f, 0.0f, 0.0f };
        const uint32_t *nb = nb_of(w, i);
        uint32_t nn = nb_len(w, i);
        if (P->scorr_k > 0.0f) {
            for (uint32_t q = 0; q < nn; q++) {
                uint32_t j = nb[q];
                v3 r = sub(xi, xyz(w->pred[j]));
                float s = -P->scorr_k * powf(pbf_cpu_poly6(P, dot(r, r)) * P->scorr_inv_wdq, P->scorr_n) * P->scorr_scale;
                dp = add(dp, scale(li + w->lambda[j] + s, pbf_cpu_grad_spiky(P, r)));
            }
        } else {
            for (uint32_t q = 0; q < nn; q++) {
                uint32_t j = nb[q];
                dp = add(dp, scale(li + w->lambda[j], pbf_cpu_grad_spiky(P, sub(xi, xyz(w->pred[j])))));
            }
        }
        dp = scale(P->mass_density * P->inv_rest_density, dp);
        v3 wall_grad;
        pbf_cpu_container_boundary(P, xi, &wall_grad);
        dp = add(dp, scale(li, wall_grad));
        v3 x = add(xi, scale(P->omega, dp));
        w->pred_out[i] = (pbf_float4){ x.x, x.y, x.z, 0.0f };
        container_collide(w, P, i);
    }
}

/// collide.comp (only with colliders): the colliders' part of the correction, computed at
/// the iteration's start (pred, lambda) and added with omega to what delta wrote, then the
/// swept collisions from the substep's start position pos[i], then the container again.
void pbf_cpu_collide(pbf_cpu_world *w, const pbf_gpu_params *P)
{
    for (uint32_t i = 0; i < w->count; i++) {
        v3 bdp = { 0.0f, 0.0f, 0.0f };
        pbf_cpu_colliders_delta(w, P, xyz(w->pred[i]), w->lambda[i], &bdp);
        v3 x = add(xyz(w->pred_out[i]), scale(P->omega, bdp));
        x = pbf_cpu_colliders_collide(w, P, xyz(w->pos[i]), x);
        w->pred_out[i] = (pbf_float4){ x.x, x.y, x.z, 0.0f };
        container_collide(w, P, i);
    }
}

/// velocity.comp: v = (x* - x) / dt with the speed clamp; x = x*.
void pbf_cpu_velocity(pbf_cpu_world *w, const pbf_gpu_params *P)
{
    for (uint32_t i = 0; i < w->count; i++) {
        v3 x = xyz(w->pred[i]);
        v3 v = scale(P->inv_dt, sub(x, xyz(w->pos[i])));
        float s = length(v);
        if (s > P->max_speed) v = scale(P->max_speed / s, v);
        w->vel[i] = (pbf_float4){ v.x, v.y, v.z, w->vel[i].w };
        w->pos[i] = (pbf_float4){ x.x, x.y, x.z, w->pos[i].w };
    }
}

static float volume_of(const pbf_gpu_params *P, float rho)
{
    return P->mass_density / fmaxf(rho, 1e-6f * P->rest_density);
}

/// vorticity.comp: omega_i = sum_j V_j grad_i W_ij x (v_j - v_i), w = |omega_i|.
void pbf_cpu_vorticity(pbf_cpu_world *w, const pbf_gpu_params *P)
{
    for (uint32_t i = 0; i < w->count; i++) {
        v3 xi = xyz(w->pos[i]), vi = xyz(w->vel[i]);
        v3 o = { 0.0f, 0.0f, 0.0f };
        const uint32_t *nb = nb_of(w, i);
        for (uint32_t q = 0, nn = nb_len(w, i); q < nn; q++) {
            uint32_t j = nb[q];
            float vol = volume_of(P, w->rho[j]);
            o = add(o, scale(vol, cross(pbf_cpu_grad_spiky(P, sub(xi, xyz(w->pos[j]))), sub(xyz(w->vel[j]), vi))));
        }
        w->omega[i] = (pbf_float4){ o.x, o.y, o.z, length(o) };
    }
}

/// viscosity.comp: vorticity confinement eps (N x omega) when eps > 0, then XSPH, into
/// vel_out (the additions in the shader's order).
void pbf_cpu_viscosity(pbf_cpu_world *w, const pbf_gpu_params *P)
{
    for (uint32_t i = 0; i < w->count; i++) {
        v3 xi = xyz(w->pos[i]), vi = xyz(w->vel[i]);
        v3 eta = { 0.0f, 0.0f, 0.0f }, xsph = { 0.0f, 0.0f, 0.0f };
        float wi = w->omega[i].w;
        const uint32_t *nb = nb_of(w, i);
        for (uint32_t q = 0, nn = nb_len(w, i); q < nn; q++) {
            uint32_t j = nb[q];
            v3 r = sub(xi, xyz(w->pos[j]));
            float vol = volume_of(P, w->rho[j]);
            if (P->vorticity > 0.0f) eta = add(eta, scale(vol * (w->omega[j].w - wi), pbf_cpu_grad_spiky(P, r)));
            xsph = add(xsph, scale(pbf_cpu_poly6(P, dot(r, r)), scale(vol, sub(xyz(w->vel[j]), vi))));
        }
        v3 v = vi;
        float le = length(eta);
        if (P->vorticity > 0.0f && le > 1e-9f)
            v = add(v, scale(P->dt * P->vorticity, cross(divide(eta, le), xyz(w->omega[i]))));
        v = add(v, scale(P->viscosity, xsph));
        w->vel_out[i] = (pbf_float4){ v.x, v.y, v.z, w->vel[i].w };
    }
    pbf_cpu_swap4(&w->vel, &w->vel_out);
}

float pbf_cpu_density_at(const pbf_cpu_world *w, const pbf_gpu_params *P, uint32_t i)
{
    v3 xi = xyz(w->pos[i]);
    float sum_w = pbf_cpu_poly6(P, 0.0f);
    const uint32_t *nb = nb_of(w, i);
    for (uint32_t q = 0, nn = nb_len(w, i); q < nn; q++) {
        v3 r = sub(xi, xyz(w->pos[nb[q]]));
        sum_w += pbf_cpu_poly6(P, dot(r, r));
    }
    float rho = P->mass_density * sum_w;
    v3 unused_wall_grad;
    rho += P->rest_density * pbf_cpu_container_boundary(P, xi, &unused_wall_grad);
    v3 unused_grad = { 0.0f, 0.0f, 0.0f };
    if (P->collider_count > 0u) pbf_cpu_colliders_density(w, P, xi, &rho, &unused_grad);
    return rho;
}

/// The parameters the metrics pass sees after a step: those of the last substep, with the
/// colliders as uploaded for that step. Before the first step the colliders stand where
