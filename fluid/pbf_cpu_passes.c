// CPU reference, the passes: each function mirrors one shader of shaders/fluid/ (named in
// its comment), per particle in slot order, in the shader's order of operations.
#include "fluid/pbf_cpu_internal.h"

#include <string.h>

// The continuous V(d) and G(d) of the boundary model (pbf_kernels.h), for the tests.
float pbf_cpu_boundary_volume(float d, float h) { return pbf_boundary_volume(d, h, 1.0f); }
float pbf_cpu_boundary_gradient(float d, float h) { return pbf_boundary_gradient(d, h, 1.0f); }
float pbf_cpu_curved_boundary(float d, float h, float R, float *G) { return pbf_curved_boundary(d, h, R, 1.0f, G); }

// ---- one function per pass, in the step's order ---------------------------------------

/// predict.comp: gravity, damping, speed clamp; x* = x + dt v.
void pbf_cpu_predict(pbf_cpu_world *w, const pbf_gpu_params *P)
{
    for (uint32_t i = 0; i < w->count; i++) {
        pbf_vec3 v = pbf_add(pbf_xyz(w->vel[i]), pbf_scale(P->dt, pbf_xyz(P->gravity)));
        v = pbf_scale(1.0f / (1.0f + P->damping * P->dt), v);
        float s = pbf_length(v);
        if (s > P->max_speed) v = pbf_scale(P->max_speed / s, v);
        w->vel[i] = (pbf_float4){ v.x, v.y, v.z, w->vel[i].w };
        pbf_vec3 x = pbf_add(pbf_xyz(w->pos[i]), pbf_scale(P->dt, v));
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

static void cell_coord(const pbf_gpu_params *P, pbf_vec3 x, int c[3])
{
    c[0] = cell_axis(x.x, P->grid_origin.x, P->inv_cell, P->grid_dims.x);
    c[1] = cell_axis(x.y, P->grid_origin.y, P->inv_cell, P->grid_dims.y);
    c[2] = cell_axis(x.z, P->grid_origin.z, P->inv_cell, P->grid_dims.z);
}

/// common.glsl's row_of and bucket_of: the row of a cell and its bucket (pbf_kernels.h
/// grid_row and grid_bucket).
static uint32_t row_of(const pbf_gpu_params *P, int y, int z) { return grid_row(P, (uint32_t)y, (uint32_t)z); }

uint32_t pbf_grid_bucket(const pbf_gpu_params *P, int x, int y, int z)
{
    return grid_bucket(P, (uint32_t)x, (uint32_t)y, (uint32_t)z);
}

/// The clears pbf_world.c issues before grid_count (cell starts and fill cursors), then
/// grid_count.comp: the cell of each position and the particles per cell. The CPU
/// reference has no sinks, so the removed bucket (w->cells) stays empty.
void pbf_cpu_grid_count(pbf_cpu_world *w, const pbf_gpu_params *P, const pbf_float4 *x)
{
    memset(w->cell_start, 0, ((size_t)w->cells + 2) * 4);
    memset(w->cell_fill, 0, ((size_t)w->cells + 1) * 4);
    for (uint32_t i = 0; i < w->count; i++) {
        int c[3];
        cell_coord(P, pbf_xyz(x[i]), c);
        w->cell_of[i] = pbf_grid_bucket(P, c[0], c[1], c[2]);
        w->cell_start[w->cell_of[i]]++;
    }
}

/// scan_block.comp and scan_add.comp: the exclusive prefix sum over all cells + 2 entries,
/// so cell c's particles are places [cell_start[c], cell_start[c + 1]).
void pbf_cpu_grid_scan(pbf_cpu_world *w)
{
    uint32_t sum = 0;
    for (uint32_t c = 0; c < w->cells + 2; c++) {
        uint32_t n = w->cell_start[c];
        w->cell_start[c] = sum;
        sum += n;
    }
}

/// grid_scatter.comp: each slot takes a place in its cell's range (sorted: place -> slot).
/// The GPU's order inside a cell depends on thread timing; here it is slot order.
void pbf_cpu_grid_scatter(pbf_cpu_world *w)
{
    for (uint32_t i = 0; i < w->count; i++) {
        uint32_t c = w->cell_of[i];
        w->sorted[w->cell_start[c] + w->cell_fill[c]++] = i;
    }
}

/// grid_sort.comp: each slot takes the rank of its slot among its cell's (a stable counting
/// sort whatever order the scatter left): order, place -> slot. A cell of more than
/// PBF_SORT_RANK_MAX particles keeps the scatter's order (the rank is quadratic in it).
void pbf_cpu_grid_sort(pbf_cpu_world *w)
{
    for (uint32_t k = 0; k < w->count; k++) {
        uint32_t me = w->sorted[k];
        uint32_t c = w->cell_of[me];
        uint32_t b = w->cell_start[c], e = w->cell_start[c + 1];
        if (e - b > PBF_SORT_RANK_MAX) {
            w->order[k] = me;
            continue;
        }
        uint32_t rank = 0;
        for (uint32_t m = b; m < e; m++) rank += w->sorted[m] < me ? 1u : 0u;
        w->order[b + rank] = me;
    }
}

/// reorder.comp: gathers the particle data into cell order, into the *_out partners.
void pbf_cpu_reorder(pbf_cpu_world *w)
{
    for (uint32_t i = 0; i < w->count; i++) {
        uint32_t j = w->order[i];
        w->pos_out[i] = w->pos[j];
        w->vel_out[i] = w->vel[j];
        w->pred_out[i] = w->pred[j];
        w->id_out[i] = w->id[j];
    }
}

static uint32_t nb_len(const pbf_cpu_world *w, uint32_t i)
{
    uint32_t n = w->nb_count[i] & ~PBF_NB_CUT;
    return n < w->max_neighbours ? n : w->max_neighbours;
}

static const uint32_t *nb_of(const pbf_cpu_world *w, uint32_t i) { return w->nb_list + (size_t)i * w->max_neighbours; }

/// density.glsl density_finish: rho_i with i's images in the container's mirrors and the
/// bodies' share, C_i and lambda_i, into lambda_rho[i] and pred[i].w.
static void density_finish(pbf_cpu_world *w, const pbf_gpu_params *P, uint32_t i, pbf_vec3 xi, uint32_t mask,
                           pbf_vec3 twice, float sum_w, pbf_vec3 grad_i, float sum_grad2)
{
    if (mask != 0u) density_add_self_images(P, xi, mask, twice, &sum_w, &grad_i, &sum_grad2);
    float rho = P->mass_density * sum_w;
    if (P->collider_count > 0u) pbf_cpu_colliders_density(w, P, xi, &rho, &grad_i);
    float lambda = density_lambda(P, rho, grad_i, sum_grad2);
    w->lambda_rho[2 * (size_t)i] = lambda;
    w->lambda_rho[2 * (size_t)i + 1] = rho;
    w->pred[i].w = lambda;
}

/// neighbours.comp slab_distance: from coordinate x to the slab of cell k (origin o, size s).
static float slab_distance(float x, float o, float s, int k)
{
    float lo = o + (float)k * s;
    return fmaxf(fmaxf(lo - x, x - (lo + s)), 0.0f);
}

/// The row of the cell a position falls in (as neighbours.comp's row_of(cell_coord(x))).
static uint32_t row_at(const pbf_gpu_params *P, pbf_vec3 x)
{
    int c[3];
    cell_coord(P, x, c);
    return row_of(P, c[1], c[2]);
}

static int min_int(int a, int b) { return a < b ? a : b; }
static int max_int(int a, int b) { return a > b ? a : b; }

void pbf_cpu_neighbours(pbf_cpu_world *w, const pbf_gpu_params *P, const pbf_float4 *x, const uint32_t *place,
                        bool solve)
{
    const int dims[3] = { (int)P->grid_dims.x, (int)P->grid_dims.y, (int)P->grid_dims.z };
    float cs = 1.0f / P->inv_cell;
    int reach = (int)ceilf(P->h * P->inv_cell - 1e-4f);
    float h2 = P->h * P->h;
    for (uint32_t i = 0; i < w->count; i++) {
        pbf_vec3 xi = pbf_xyz(x[i]);
        int c[3];
        cell_coord(P, xi, c);
        uint32_t n = 0, *list = w->nb_list + (size_t)i * w->max_neighbours;
        float sum_w = w_spiky(P, 0.0f);
        pbf_vec3 grad_i = { 0.0f, 0.0f, 0.0f };
        float sum_grad2 = 0.0f;
        pbf_vec3 twice;
        uint32_t mask = mirror_mask(P, xi, &twice);
        // Rows of cells (fixed y, z) in z then y order, each trimmed to the x cells the
        // kernel sphere reaches; rows whose y-z slab lies farther than h are skipped.
        // The search stops at max_neighbours + 1 found (an overflow: counted, not listed),
        // so a pile of particles in one cell costs no more than a full list each, and after
        // PBF_CANDIDATES_PER_ENTRY x max_neighbours candidates (PBF_NB_CUT in the count: an
        // overflow, the neighbours found so far still listed).
        uint32_t stop = w->max_neighbours, budget = PBF_CANDIDATES_PER_ENTRY * w->max_neighbours, cut = 0;
        for (int z = max_int(c[2] - reach, 0); z <= min_int(c[2] + reach, dims[2] - 1) && n <= stop && !cut; z++) {
            float dz = slab_distance(xi.z, P->grid_origin.z, cs, z);
            for (int y = max_int(c[1] - reach, 0); y <= min_int(c[1] + reach, dims[1] - 1) && n <= stop && !cut; y++) {
                float dy = slab_distance(xi.y, P->grid_origin.y, cs, y);
                float ryz = dy * dy + dz * dz;
                if (ryz >= h2) continue;
                float rx = sqrtf(h2 - ryz);
                int x0 = max_int((int)floorf((xi.x - rx - P->grid_origin.x) * P->inv_cell), 0);
                int x1 = min_int((int)floorf((xi.x + rx - P->grid_origin.x) * P->inv_cell), dims[0] - 1);
                // Buckets b0..b1 of this row, wrapping past the last into the first; other
                // rows that share them are skipped by their row number.
                uint32_t row = row_of(P, y, z), b0 = pbf_grid_bucket(P, x0, y, z), b1 = pbf_grid_bucket(P, x1, y, z);
                int ranges = b0 <= b1 ? 1 : 2;
                for (int part = 0; part < ranges && n <= stop && !cut; part++) {
                    uint32_t b = w->cell_start[part == 0 ? b0 : 0u];
                    uint32_t e = w->cell_start[(part == 0 && ranges == 1) || part == 1 ? b1 + 1u : P->grid_dims.w];
                    for (uint32_t k = b; k < e && n <= stop && !cut; k++) {
                        if (budget == 0) { // looked at enough candidates: an overflow
                            cut = PBF_NB_CUT;
                            break;
                        }
                        budget--;
                        uint32_t j = place ? place[k] : k;
                        pbf_vec3 xj = pbf_xyz(x[j]);
                        pbf_vec3 r = pbf_sub(xi, xj);
                        if (pbf_dot(r, r) < h2 && j != i && row_at(P, xj) == row) {
                            if (n < w->max_neighbours) {
                                list[n] = j;
                                if (solve) density_add(P, r, &sum_w, &grad_i, &sum_grad2);
                            }
                            n++;
                        }
                    }
                }
            }
        }
        w->nb_count[i] = n | cut;
        if (solve && mask != 0u) // next to a wall: the neighbours' images
            for (uint32_t q = 0, nn = nb_len(w, i); q < nn; q++)
                density_add_images(P, xi, pbf_xyz(x[list[q]]), mask, twice, &sum_w, &grad_i, &sum_grad2);
        if (solve) density_finish(w, P, i, xi, mask, twice, sum_w, grad_i, sum_grad2);
    }
}

/// density.comp (iterations after the first): rho_i and lambda_i over the neighbour list.
void pbf_cpu_density(pbf_cpu_world *w, const pbf_gpu_params *P)
{
    for (uint32_t i = 0; i < w->count; i++) {
        pbf_vec3 xi = pbf_xyz(w->pred[i]);
        float sum_w = w_spiky(P, 0.0f);
        pbf_vec3 grad_i = { 0.0f, 0.0f, 0.0f };
        float sum_grad2 = 0.0f;
        const uint32_t *nb = nb_of(w, i);
        pbf_vec3 twice;
        uint32_t mask = mirror_mask(P, xi, &twice);
        for (uint32_t q = 0, nn = nb_len(w, i); q < nn; q++)
            density_add(P, pbf_sub(xi, pbf_xyz(w->pred[nb[q]])), &sum_w, &grad_i, &sum_grad2);
        if (mask != 0u) // next to a wall: the neighbours' images
            for (uint32_t q = 0, nn = nb_len(w, i); q < nn; q++)
                density_add_images(P, xi, pbf_xyz(w->pred[nb[q]]), mask, twice, &sum_w, &grad_i, &sum_grad2);
        density_finish(w, P, i, xi, mask, twice, sum_w, grad_i, sum_grad2);
    }
}

/// The collisions delta.comp and collide.comp both end with: a particle radius from every
/// container plane, then the domain clamp, on pred_out[i].
static void container_collide(pbf_cpu_world *w, const pbf_gpu_params *P, uint32_t i, pbf_vec3 x)
{
    for (uint32_t p = 0; p < P->plane_count; p++) {
        pbf_vec3 n;
        float d = plane_distance(P, p, x, &n);
        if (d < P->radius) x = pbf_add(x, pbf_scale(P->radius - d, n));
    }
    x.x = pbf_clamp(x.x, P->domain_min.x + P->radius, P->domain_max.x - P->radius);
    x.y = pbf_clamp(x.y, P->domain_min.y + P->radius, P->domain_max.y - P->radius);
    x.z = pbf_clamp(x.z, P->domain_min.z + P->radius, P->domain_max.z - P->radius);
    w->pred_out[i] = (pbf_float4){ x.x, x.y, x.z, 0.0f };
}

/// delta.comp: the correction from the fluid (lambda of each particle in pred.w) and the
/// container, times the iteration's factor relax, then the container's collisions and the
/// domain clamp, into pred_out.
void pbf_cpu_delta(pbf_cpu_world *w, const pbf_gpu_params *P, float relax, bool apply_level)
{
    for (uint32_t i = 0; i < w->count; i++) {
        pbf_vec3 xi = pbf_xyz(w->pred[i]);
        float li = w->pred[i].w;
        pbf_vec3 dp = { 0.0f, 0.0f, 0.0f };
        const uint32_t *nb = nb_of(w, i);
        uint32_t nn = nb_len(w, i);
        pbf_vec3 twice;
        uint32_t mask = mirror_mask(P, xi, &twice);
        if (mask != 0u) { // next to a wall: the neighbours' images too, and i's own
            for (uint32_t q = 0; q < nn; q++) {
                pbf_float4 pj = w->pred[nb[q]];
                dp = pbf_add(dp, mirrored_correction(P, xi, pbf_xyz(pj), li + pj.w, mask, twice));
            }
            dp = pbf_add(dp, self_image_correction(P, xi, li, mask, twice));
        }
        if (P->scorr_k > 0.0f) {
            for (uint32_t q = 0; q < nn; q++) {
                pbf_float4 pj = w->pred[nb[q]];
                pbf_vec3 r = pbf_sub(xi, pbf_xyz(pj));
                dp = pbf_add(dp, pbf_scale(li + pj.w + scorr_of(P, r), grad_spiky(P, r)));
            }
        } else {
            for (uint32_t q = 0; q < nn; q++) {
                pbf_float4 pj = w->pred[nb[q]];
                dp = pbf_add(dp, pbf_scale(li + pj.w, grad_spiky(P, pbf_sub(xi, pbf_xyz(pj)))));
            }
        }
        dp = pbf_scale(P->mass_density * P->inv_rest_density, dp);
        pbf_vec3 x = pbf_add(xi, pbf_scale(relax, dp));
        if (apply_level) x = pbf_add(x, level_correction(P, w->level, xi));
        container_collide(w, P, i, x);
    }
}

/// collide.comp (only with colliders): the colliders' part of the correction, computed at
/// the iteration's start (pred, lambda in pred.w) and added times relax to what delta wrote,
/// in the coarse level's iteration the colliders' reaction to its push, then the swept
/// collisions from the substep's start position pos[i], then the container.
void pbf_cpu_collide(pbf_cpu_world *w, const pbf_gpu_params *P, float relax, bool apply_level)
{
    for (uint32_t i = 0; i < w->count; i++) {
        pbf_float4 pi = w->pred[i];
        pbf_vec3 bdp = { 0.0f, 0.0f, 0.0f };
        float level_lambda = apply_level ? -level_pressure(P, w->level, pbf_xyz(pi)) : 0.0f;
        pbf_cpu_colliders_delta(w, P, pbf_xyz(pi), pi.w, relax, level_lambda, pbf_xyz(w->pos[i]), &bdp);
        pbf_vec3 x = pbf_add(pbf_xyz(w->pred_out[i]), pbf_scale(relax, bdp));
        x = pbf_cpu_colliders_collide(w, P, pbf_xyz(w->pos[i]), x);
        container_collide(w, P, i, x);
    }
}

/// velocity.comp: v = (x* - x) / dt with the speed clamp, w = the volume m / rho from the
/// last density pass; x = x*.
void pbf_cpu_velocity(pbf_cpu_world *w, const pbf_gpu_params *P)
{
    for (uint32_t i = 0; i < w->count; i++) {
        pbf_vec3 x = pbf_xyz(w->pred[i]);
        pbf_vec3 v = pbf_scale(P->inv_dt, pbf_sub(x, pbf_xyz(w->pos[i])));
        float s = pbf_length(v);
        if (s > P->max_speed) v = pbf_scale(P->max_speed / s, v);
        if (P->wall_friction > 0.0f) v = wall_friction_of(P, x, v);
        float volume = P->mass / fmaxf(w->lambda_rho[2 * (size_t)i + 1], 1e-6f * P->rest_density);
        w->vel[i] = (pbf_float4){ v.x, v.y, v.z, volume };
        w->pos[i] = (pbf_float4){ x.x, x.y, x.z, w->pos[i].w };
    }
}

/// vorticity.comp: omega_i, the curl of the corrected velocity gradient (corrected_curl), V_j
/// in vel[j].w; w = |omega_i|.
void pbf_cpu_vorticity(pbf_cpu_world *w, const pbf_gpu_params *P)
{
    for (uint32_t i = 0; i < w->count; i++) {
        pbf_vec3 xi = pbf_xyz(w->pos[i]), vi = pbf_xyz(w->vel[i]);
        pbf_vec3 bx = { 0.0f, 0.0f, 0.0f }, by = bx, bz = bx, ad = bx, ao = bx;
        const uint32_t *nb = nb_of(w, i);
        for (uint32_t q = 0, nn = nb_len(w, i); q < nn; q++) {
            uint32_t j = nb[q];
            pbf_float4 vj = w->vel[j];
            pbf_vec3 dx = pbf_sub(pbf_xyz(w->pos[j]), xi);
            pbf_vec3 g = pbf_scale(vj.w, grad_spiky(P, pbf_neg(dx)));
            pbf_vec3 dv = pbf_sub(pbf_xyz(vj), vi);
            bx = pbf_add(bx, pbf_scale(dv.x, g));
            by = pbf_add(by, pbf_scale(dv.y, g));
            bz = pbf_add(bz, pbf_scale(dv.z, g));
            ad = pbf_add(ad, (pbf_vec3){ dx.x * g.x, dx.y * g.y, dx.z * g.z });
            ao = pbf_add(ao, (pbf_vec3){ dx.x * g.y, dx.x * g.z, dx.y * g.z });
        }
        pbf_vec3 o = corrected_curl(bx, by, bz, ad, ao);
        w->omega[i] = (pbf_float4){ o.x, o.y, o.z, pbf_length(o) };
    }
}

/// viscosity.comp: vorticity confinement eps (N x omega) when eps > 0, then XSPH, into
/// vel_out (the additions in the shader's order).
void pbf_cpu_viscosity(pbf_cpu_world *w, const pbf_gpu_params *P)
{
    for (uint32_t i = 0; i < w->count; i++) {
        pbf_vec3 xi = pbf_xyz(w->pos[i]), vi = pbf_xyz(w->vel[i]);
        pbf_vec3 xsph = { 0.0f, 0.0f, 0.0f };
        const uint32_t *nb = nb_of(w, i);
        uint32_t nn = nb_len(w, i);
        pbf_vec3 v = vi;
        if (P->vorticity > 0.0f) {
            float wi = w->omega[i].w;
            pbf_vec3 eta = { 0.0f, 0.0f, 0.0f };
            for (uint32_t q = 0; q < nn; q++) {
                uint32_t j = nb[q];
                pbf_vec3 r = pbf_sub(xi, pbf_xyz(w->pos[j]));
                pbf_float4 vj = w->vel[j];
                eta = pbf_add(eta, pbf_scale(vj.w * (w->omega[j].w - wi), grad_spiky(P, r)));
                xsph = pbf_add(xsph, pbf_scale(w_poly6(P, pbf_dot(r, r)), pbf_scale(vj.w, pbf_sub(pbf_xyz(vj), vi))));
            }
            v = pbf_add(v, confinement_dv(P, eta, pbf_xyz(w->omega[i]), wi));
        } else {
            for (uint32_t q = 0; q < nn; q++) {
                uint32_t j = nb[q];
                pbf_vec3 r = pbf_sub(xi, pbf_xyz(w->pos[j]));
                pbf_float4 vj = w->vel[j];
                xsph = pbf_add(xsph, pbf_scale(w_poly6(P, pbf_dot(r, r)), pbf_scale(vj.w, pbf_sub(pbf_xyz(vj), vi))));
            }
        }
        v = pbf_add(v, pbf_scale(P->viscosity, xsph));
        w->vel_out[i] = (pbf_float4){ v.x, v.y, v.z, w->vel[i].w };
    }
}

/// tension.comp: a_i = sum_j tension_pair(...) at x*, into tension[i], and x* + dt^2 a_i
/// (lambda kept) into pred_out.
void pbf_cpu_tension(pbf_cpu_world *w, const pbf_gpu_params *P)
{
    for (uint32_t i = 0; i < w->count; i++) {
        pbf_vec3 xi = pbf_xyz(w->pred[i]);
        float rho_i = P->mass / fmaxf(w->vel[i].w, 1e-12f);
        pbf_vec3 a = { 0.0f, 0.0f, 0.0f };
        const uint32_t *nb = nb_of(w, i);
        for (uint32_t q = 0, nn = nb_len(w, i); q < nn; q++) {
            uint32_t j = nb[q];
            a = pbf_add(a, tension_pair(P, pbf_sub(xi, pbf_xyz(w->pred[j])), rho_i, P->mass / fmaxf(w->vel[j].w, 1e-12f)));
        }
        w->tension[i] = (pbf_float4){ a.x, a.y, a.z, 0.0f };
        pbf_vec3 x = pbf_add(xi, pbf_scale(P->dt * P->dt, a));
        w->pred_out[i] = (pbf_float4){ x.x, x.y, x.z, w->pred[i].w };
    }
}

/// The coarse level's passes (level_deposit.comp, level_prepare.comp, level_sweep.comp): the
/// deposit in the same fixed point (integer sums: any order gives the GPU's), then the sweeps,
/// red cells then black, each colour reading only the other.
void pbf_cpu_level(pbf_cpu_world *w, const pbf_gpu_params *P)
{
    pbf_gpu_level_cell *level = w->level;
    uint32_t cells = P->level_dims.w;
    for (uint32_t i = 0; i < w->count; i++) {
        float e;
        if (!level_excess(P, w->lambda_rho[2 * i + 1], &e)) continue;
        pbf_vec3 x = pbf_xyz(w->pred[i]);
        for (int k = 0; k < 8; k++) {
            uint32_t cell;
            float wgt = level_corner(P, x, k, &cell);
            // As the GPU's integer atomics: wrapping (a pile of 32 768 particles in a cell).
            level[cell].weight = (int32_t)((uint32_t)level[cell].weight + (uint32_t)level_fixed(wgt));
            level[cell].excess = (int32_t)((uint32_t)level[cell].excess + (uint32_t)level_fixed(wgt * e));
        }
    }
    for (uint32_t c = 0; c < cells; c++) {
        level[c].e = level_compression(P, level[c].weight, level[c].excess);
        level[c].p = 0.0f;
        level[c].weight = 0;
        level[c].excess = 0;
    }
    for (int sweep = 0; sweep < w->params.level_sweeps; sweep++)
        for (uint32_t parity = 0; parity < 2; parity++)
            for (uint32_t id = 0; id < cells; id++)
                if (level_parity(P, id) == parity) level[id].p = level_relaxed(P, level, id);
}

/// metrics.comp's density of slot i at its position (fluid over the list + boundaries).
float pbf_cpu_density_at(const pbf_cpu_world *w, const pbf_gpu_params *P, uint32_t i)
{
    pbf_vec3 xi = pbf_xyz(w->pos[i]);
    float sum_w = w_spiky(P, 0.0f);
    const uint32_t *nb = nb_of(w, i);
    pbf_vec3 twice;
    uint32_t mask = mirror_mask(P, xi, &twice);
    pbf_vec3 unused_grad = { 0.0f, 0.0f, 0.0f };
    float unused_grad2 = 0.0f;
    for (uint32_t q = 0, nn = nb_len(w, i); q < nn; q++) sum_w += w_spiky(P, pbf_length(pbf_sub(xi, pbf_xyz(w->pos[nb[q]]))));
    if (mask != 0u) { // next to a wall: the neighbours' images and its own
        for (uint32_t q = 0, nn = nb_len(w, i); q < nn; q++)
            density_add_images(P, xi, pbf_xyz(w->pos[nb[q]]), mask, twice, &sum_w, &unused_grad, &unused_grad2);
        density_add_self_images(P, xi, mask, twice, &sum_w, &unused_grad, &unused_grad2);
    }
    float rho = P->mass_density * sum_w;
    if (P->collider_count > 0u) pbf_cpu_colliders_density(w, P, xi, &rho, &unused_grad);
    return rho;
}
