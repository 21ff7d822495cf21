#!/bin/sh
# Breaks one render pass at a time in a copy of shaders/ and runs tests/test_surface.c
# against it (SEICHE_SHADER_DIR), to show that the image tests catch each broken pass.
# Prints, per mutation, the tests that failed; a mutation no test catches, or one whose
# line is no longer in the shader (the shader changed: update this list), is reported
# and makes the script exit 1.
#   make build && tools/surface_mutations.sh
cd "$(dirname "$0")/.." || exit 2
[ -x build/bin/test_surface ] || { echo "build first: make build" >&2; exit 2; }
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
status=0

# name | file | text to find | replacement
mutate() {
    rm -rf "$tmp/shaders"
    cp -r shaders "$tmp/shaders"
    f="$tmp/shaders/render/$2"
    if ! grep -qF -- "$3" "$f"; then
        echo "STALE   $1: '$3' is not in shaders/render/$2"
        status=1
        return
    fi
    FIND="$3" REPL="$4" perl -0pi -e 's/\Q$ENV{FIND}\E/$ENV{REPL}/' "$f"
    SEICHE_GL_STRICT=1 SEICHE_SHADER_DIR="$tmp/shaders" build/bin/test_surface >"$tmp/log" 2>&1
    failed=$(sed -n 's/^\[  FAILED  \] \([a-z_]*\)$/\1/p' "$tmp/log" | sort -u | tr '\n' ' ')
    if [ -z "$failed" ]; then
        echo "MISSED  $1"
        status=1
    else
        echo "caught  $1: $failed"
    fi
}

mutate "blank surface (composite never shades water)" composite.frag \
    "if (z <= 0.0 || depth >= scene_z) {" "if (true) {"
mutate "inverted normals" composite.frag \
    "vec3 n_view = normalize(cross(ddx, ddy));" "vec3 n_view = normalize(cross(ddy, ddx));"
mutate "unsmoothed depth (filter returns its input)" smooth.frag \
    "o_depth = sum / wsum;" "o_depth = z0;"
mutate "smoothing across layers (no narrow range)" smooth.frag \
    "if (za > 0.0 && za <= hi) {" "if (za > 0.0) {"
mutate "no thickness (thickness pass writes 0)" fluid_thickness.frag \
    "o_thickness = 2.0 * sqrt(h) * u_fill;" "o_thickness = 0.0;"
mutate "no absorption" composite.frag \
    "vec3 transmit = exp(-u_absorption * thick);" "vec3 transmit = vec3(1.0);"
mutate "flat splats (quad depth, not the sphere's)" fluid_depth.frag \
    "o_depth = -hit.z;" "o_depth = -v_center.z;"
mutate "water depth not written" composite.frag \
    "gl_FragDepth = depth;" "gl_FragDepth = scene_z;"
mutate "no refraction of the scene behind" composite.frag \
    "vec3 behind = textureLod(u_scene_color, uv_r, 0.0).rgb;" "vec3 behind = vec3(0.5);"
mutate "no Fresnel reflection" composite.frag \
    "vec3 c = mix(inside, env, fresnel) + spec;" "vec3 c = inside + spec;"
mutate "no opaque shadows" frame.glsl \
    "vis *= 1.0 / 9.0;" "vis = 1.0;"
mutate "no water in the shadow map" frame.glsl \
    "return vis * exp(-u_water_light.rgb * inside);" "return vec3(vis);"
mutate "no spray" spray.frag \
    "o_color = vec4(fog(c, pw), u_spray * v_alpha * edge * edge);" "o_color = vec4(0.0);"
exit $status
