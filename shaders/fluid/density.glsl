// The density constraint of one particle, shared by density.comp (every iteration) and
// neighbours.comp (which computes the first iteration's density while it finds the
// neighbours, saving a pass per substep). Included after common.glsl and colliders.glsl,
// with USE_PRED, USE_LAMBDA and USE_COLLIDERS.

// Adds neighbour j at r = x_i - x_j to the sums: sum W (poly6), grad_i C_i (fluid part,
// 1/m) and sum_j |grad_j C_i|^2 (1/m^2).
void density_add(vec3 r, inout float sum_w, inout vec3 grad_i, inout float sum_grad2)
{
    float k = P.mass_density * P.inv_rest_density;
    sum_w += w_poly6(dot(r, r));
    vec3 g = k * grad_spiky(r);
    grad_i += g;
    sum_grad2 += dot(g, g);
}

// rho_i from the fluid sums plus the boundaries' share, C_i = max(rho_i / rho0 - 1, 0),
// lambda_i = -C_i / (sum_k |grad_k C_i|^2 + epsilon); stored in lambda_rho[i] and in
// pred[i].w (the delta pass reads a neighbour's position and multiplier in one load;
// other threads only read pred[j].xyz while this is written).
void density_finish(uint i, vec3 xi, float sum_w, vec3 grad_i, float sum_grad2)
{
    float rho = P.mass_density * sum_w;
    vec3 wall_grad;
    rho += P.rest_density * container_boundary(xi, wall_grad);
    grad_i += wall_grad;
    if (P.collider_count > 0u) colliders_density(xi, rho, grad_i);
    float C = max(rho * P.inv_rest_density - 1.0, 0.0);
    float lambda = -C / (dot(grad_i, grad_i) + sum_grad2 + P.epsilon);
    lambda_rho[i] = vec2(lambda, rho);
    pred[i].w = lambda;
}
