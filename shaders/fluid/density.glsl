// The density constraint of one particle, shared by density.comp (every iteration) and
// neighbours.comp (which computes the first iteration's density while it finds the
// neighbours, saving a pass per substep). Included after common.glsl and colliders.glsl,
// with USE_PRED, USE_LAMBDA and USE_COLLIDERS. The sums (density_add) and the multiplier
// (density_lambda) are pbf_kernels.h's, shared with the CPU reference.

// rho_i from the fluid sums (with the container's mirror images) plus the bodies' share, C_i = max(rho_i / rho0 - 1, 0),
// lambda_i = -C_i / (sum_k |grad_k C_i|^2 + epsilon); stored in lambda_rho[i] and in
// pred[i].w (the delta pass reads a neighbour's position and multiplier in one load;
// other threads only read pred[j].xyz while this is written).
void density_finish(uint i, vec3 xi, uint mask, vec3 twice, float sum_w, vec3 grad_i, float sum_grad2)
{
    if (mask != 0u) density_add_self_images(xi, mask, twice, sum_w, grad_i, sum_grad2);
    float rho = P.mass_density * sum_w;
    if (P.collider_count > 0u) colliders_density(xi, rho, grad_i);
    float lambda = density_lambda(rho, grad_i, sum_grad2);
    lambda_rho[i] = vec2(lambda, rho);
    pred[i].w = lambda;
}
