// v / |v| for a v of any size in float range: brought first to a largest component in [1, 2)
// by a power of two (scale_to_unit, height.glsl). normalize's squared length vanishes for
// vectors under about 1e-19 (an object 1e-20 across lost its highlights: the view vector's
// length was 0; found by an exploratory session, forty-first) and overflows past 1e19. The
// zero vector gives NaN, as normalize's does.
vec3 unit_vector(vec3 v)
{
    vec3 a = abs(v);
    return normalize(v * scale_to_unit(max(max(a.x, a.y), a.z)));
}

// Blinn-Phong with one directional light (energy-normalized specular lobe).
// n: unit shading normal, l: unit direction towards the light, v: unit direction towards the
// eye, all world space. Returns linear RGB.
// `visibility` (0..1) scales the direct light (self-shadowing); ambient stays.
vec3 shade_blinn_phong(vec3 albedo, vec3 n, vec3 l, vec3 v, float visibility)
{
    const float ambient = u_material.x;
    const float diffuse = u_material.y;
    const float specular = u_material.z;
    const float shininess = u_material.w;
    float n_dot_l = max(dot(n, l), 0.0);
    vec3 h = normalize(l + v);
    float spec = n_dot_l > 0.0
        ? (shininess + 8.0) / (8.0 * 3.14159265) * pow(max(dot(n, h), 0.0), shininess)
        : 0.0;
    return albedo * (ambient + diffuse * n_dot_l * visibility) + vec3(specular * spec * visibility);
}

vec3 shade_blinn_phong(vec3 albedo, vec3 n, vec3 l, vec3 v)
{
    return shade_blinn_phong(albedo, n, l, v, 1.0);
}
