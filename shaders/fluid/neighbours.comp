#version 430
// Stage neighbours: once per substep, after the reorder, each particle lists the slots of
// the particles within h of its predicted position (the paper's "find neighbours"); the
// solver iterations and the velocity passes then walk the list instead of the grid.
// Particles are stored in bucket order and a row of cells (fixed y, z) takes consecutive
// buckets (common.glsl bucket_of), so the x cells the kernel sphere reaches in a row are
// one contiguous range of slots, or two where the buckets wrap. Rows whose y-z slab lies
// farther than h are skipped. Other rows that share the same buckets are skipped by their
// row number, so each neighbour is found once.
// A particle with more neighbours than the list holds keeps the first max_neighbours found
// (in cell order) and is counted in the metrics (overflow); nothing is written out of bounds.
// The search stops at max_neighbours + 1 found, so a pile of particles in one cell (a
// diverged solve) costs a full list each, not the whole pile each; and after
// PBF_CANDIDATES_PER_ENTRY x max_neighbours candidates, flagged in the count (PBF_NB_CUT:
// an overflow, the neighbours found so far still listed), so a crowd of particles that are
// not neighbours (colliding rows, non-finite positions) costs a bounded search as well.
// The first iteration's density and lambda are computed here too, from the listed
// neighbours in list order (exactly what density.comp would do next), saving a pass.
#define USE_PRED
#define WRITE_PRED
#define USE_CELL_START
#define USE_NB
#define WRITE_NB
#define USE_LAMBDA
#define WRITE_LAMBDA
#define USE_COLLIDERS
#include "common.glsl"
#include "colliders.glsl"
#include "density.glsl"
layout(local_size_x = PBF_WG) in;

// Distance along one axis from coordinate x to the slab of cell k (origin o, size s).
float slab_distance(float x, float o, float s, int k)
{
    float lo = o + float(k) * s;
    return max(max(lo - x, x - (lo + s)), 0.0);
}

void main()
{
    uint i = gl_GlobalInvocationID.x;
    if (i >= particle_count()) return;
    vec3 xi = pred[i].xyz;
    ivec3 c = cell_coord(xi);
    ivec3 dims = ivec3(P.grid_dims.xyz);
    float cs = 1.0 / P.inv_cell;
    int reach = int(ceil(P.h * P.inv_cell - 1e-4));
    float h2 = P.h * P.h;
    uint n = 0u;
    float sum_w = w_spiky(0.0);
    vec3 grad_i = vec3(0.0);
    float sum_grad2 = 0.0;
    vec3 twice;
    uint mask = mirror_mask(xi, twice);
    uint stop = P.max_neighbours;
    uint budget = PBF_CANDIDATES_PER_ENTRY * P.max_neighbours;
    uint cut = 0u;
    for (int z = max(c.z - reach, 0); z <= min(c.z + reach, dims.z - 1) && n <= stop && cut == 0u; z++) {
        float dz = slab_distance(xi.z, P.grid_origin.z, cs, z);
        for (int y = max(c.y - reach, 0); y <= min(c.y + reach, dims.y - 1) && n <= stop && cut == 0u; y++) {
            float dy = slab_distance(xi.y, P.grid_origin.y, cs, y);
            float ryz = dy * dy + dz * dz;
            if (ryz >= h2) continue;
            float rx = sqrt(h2 - ryz);
            int x0 = max(int(floor((xi.x - rx - P.grid_origin.x) * P.inv_cell)), 0);
            int x1 = min(int(floor((xi.x + rx - P.grid_origin.x) * P.inv_cell)), dims.x - 1);
            uint row = row_of(ivec3(x0, y, z));
            uint b0 = bucket_of(ivec3(x0, y, z)), b1 = bucket_of(ivec3(x1, y, z));
            // Buckets b0..b1 in order, wrapping past the last bucket into the first.
            uint ranges = b0 <= b1 ? 1u : 2u;
            for (uint part = 0u; part < ranges && n <= stop && cut == 0u; part++) {
                uint b = cell_start[part == 0u ? b0 : 0u];
                uint e = cell_start[(part == 0u && ranges == 1u) || part == 1u ? b1 + 1u : P.grid_dims.w];
                for (uint j = b; j < e && n <= stop && cut == 0u; j++) {
                    if (budget == 0u) { // looked at enough: an overflow; the list keeps what it has
                        cut = PBF_NB_CUT;
                        break;
                    }
                    budget--;
                    vec3 pj = pred[j].xyz;
                    vec3 r = xi - pj;
                    if (dot(r, r) < h2 && j != i && row_of(cell_coord(pj)) == row) {
                        if (n < P.max_neighbours) {
                            nb_list[nb_index(i, n)] = j;
                            density_add(r, sum_w, grad_i, sum_grad2);
                        }
                        n++;
                    }
                }
            }
        }
    }
    nb_count[i] = n | cut;
    if (mask != 0u) { // next to a wall: the neighbours' images
        uint nn = min(n, P.max_neighbours);
        for (uint q = 0u; q < nn; q++) density_add_images(xi, pred[nb_at(i, q)].xyz, mask, twice, sum_w, grad_i, sum_grad2);
    }
    density_finish(i, xi, mask, twice, sum_w, grad_i, sum_grad2);
}
