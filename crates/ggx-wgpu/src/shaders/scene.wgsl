// ggx path tracer, part 1: scene bindings, BVH2 traversal (obvhs's ray_traverse_dynamic),
// area lights, the environment, punctual lights, texture coordinates and textures (ggx-scene).
// Expects ggx_core.wgsl in front of it.

const STACK_SIZE: u32 = 64u;
const NO_INDEX: u32 = 0xffffffffu;
const FLT_EPSILON: f32 = 1.1920929e-7f;
const ENV_NONE: u32 = 0u;
const ENV_CONSTANT: u32 = 1u;
const ENV_MAP: u32 = 2u;
// ggx-scene texture.rs flags.
const TEXTURE_FLOAT: u32 = 1u;
const TEXTURE_NEAREST: u32 = 2u;
const TEXTURE_WRAP_S_SHIFT: u32 = 2u;
const TEXTURE_WRAP_T_SHIFT: u32 = 4u;
const REF_SRGB: u32 = 1u;
const REF_CHANNEL_SHIFT: u32 = 1u;
const WRAP_CLAMP_TO_EDGE: u32 = 1u;
const WRAP_MIRRORED_REPEAT: u32 = 2u;
// ggx-scene punctual.rs kinds.
const PUNCTUAL_SPOT: u32 = 1u;
const PUNCTUAL_DIRECTIONAL: u32 = 2u;

struct Params {
    cam_position: vec3<f32>,
    tan_half_fov: f32,
    cam_forward: vec3<f32>,
    aspect: f32,
    cam_right: vec3<f32>,
    width_f: f32,
    cam_up: vec3<f32>,
    height_f: f32,
    env_radiance: vec3<f32>,
    env_scale: f32,
    env_to_map: vec4<f32>,
    env_to_world: vec4<f32>,
    width: u32,
    height: u32,
    y0: u32,
    rows: u32,
    s0: u32,
    s1: u32,
    sequence: u32,
    seed: u32,
    light_strategy: u32,
    max_depth: u32,
    roulette_depth: u32,
    draw_lobe: u32,
    emitter_count: u32,
    env_kind: u32,
    env_width: u32,
    env_height: u32,
    light_cdf: u32,
    env_func: u32,
    env_conditional_cdf: u32,
    env_marginal_cdf: u32,
    env_texels: u32,
    env_marginal_integral: f32,
    energy_tables: u32,
    uvs: u32,
    uv_count: u32,
    tangents: u32,
    tangent_count: u32,
    texture_infos: u32,
    texture_count: u32,
    texture_unorm: u32,
    texture_words: u32,
    punctual_lights: u32,
    punctual_count: u32,
    emitters: u32,
    env_light: u32,
    pad3: u32,
}

struct BvhNode {
    min: vec3<f32>,
    prim_count: u32,
    max: vec3<f32>,
    first_index: u32,
}

struct Triangle {
    v0: vec3<f32>,
    material: u32,
    v1: vec3<f32>,
    normals: u32,
    v2: vec3<f32>,
    emitter: u32,
}

struct ShadingNormals {
    normals: array<vec4<f32>, 3>,
}

struct Material {
    conductor: GgxConductor,
    albedo: vec3<f32>,
    kind: u32,
    emission: vec3<f32>,
    ior: f32,
    extra: vec3<f32>,
    sampling: u32,
    compensation: u32,
    surface: u32,
    specular_weight: f32,
    p_specular: f32,
}

struct Emitter {
    triangle: u32,
    light: u32,
    area: f32,
    pmf: f32,
}

// ggx-scene TextureInfo: texels at `offset` in the word table, width x height, flags.
struct TextureInfo {
    offset: u32,
    width: u32,
    height: u32,
    flags: u32,
}

// ggx-scene TextureRef: texture index (NO_INDEX: none), flags, row-major 2x3 transform of (u, v, 1).
struct TextureRef {
    texture: u32,
    flags: u32,
    s: vec3<f32>,
    t: vec3<f32>,
}

// ggx-scene PunctualLight (64 bytes): a point, spot or directional light in world space.
struct PunctualLight {
    position: vec3<f32>,
    kind: u32,
    direction: vec3<f32>,
    range: f32,
    intensity: vec3<f32>,
    spot_scale: f32,
    spot_offset: f32,
    pad: array<u32, 3>,
}

struct CdfPick {
    index: u32,
    du: f32,
}

struct Ray {
    origin: vec3<f32>,
    dir: vec3<f32>,
    inv_dir: vec3<f32>,
    tmax: f32,
}

// Read-only storage, not uniform: lavapipe re-specializes a kernel on every new value of a uniform that
// steers control flow (y0, s0...), which cost 2 s per dispatch.
@group(0) @binding(0) var<storage, read> params: Params;
@group(0) @binding(1) var<storage, read> nodes: array<BvhNode>;
@group(0) @binding(2) var<storage, read> triangles: array<Triangle>;
@group(0) @binding(3) var<storage, read> shading_normals: array<ShadingNormals>;
@group(0) @binding(4) var<storage, read> materials: array<Material>;
@group(0) @binding(5) var<storage, read> table: array<f32>;
@group(0) @binding(6) var<storage, read_write> output: array<vec4<f32>>;
// Emitters, textured materials, punctual lights, texture coordinates, tangents, textures (scene_upload.rs
// `SceneTables::surface`).
@group(0) @binding(7) var<storage, read> surface: array<u32>;

// energy.wgsl's table accessor: ggx-core's energy tables, appended to `table` at params.energy_tables.
fn energy_table(i: u32) -> f32 {
    return table[params.energy_tables + i];
}

// glam's normalize_or_zero: v (1 / |v|) when that is finite and positive, else 0.
fn glam_normalize_or_zero(v: vec3<f32>) -> vec3<f32> {
    let rcp = 1.0 / sqrt(dot3(v, v));
    return select(vec3(0.0), v * rcp, is_finite(rcp) && rcp > 0.0);
}

// Triangle::geometric_normal: normalize((v1 - v0) x (v2 - v0)), 0 when degenerate.
fn geometric_normal(tri: Triangle) -> vec3<f32> {
    return glam_normalize_or_zero(cross3(tri.v1 - tri.v0, tri.v2 - tri.v0));
}

// ShadingNormals::interpolate: normalize(b0 n0 + b1 n1 + b2 n2), b0 = 1 - b1 - b2.
fn interpolate_normal(n: ShadingNormals, b1: f32, b2: f32) -> vec3<f32> {
    let v = (1.0 - b1 - b2) * n.normals[0].xyz + b1 * n.normals[1].xyz + b2 * n.normals[2].xyz;
    return glam_normalize_or_zero(v);
}

// obvhs safe_inverse: 1 / x, or sign(x) / EPSILON when |x| <= EPSILON (+-0 give +-1 / EPSILON).
fn safe_inverse(x: f32) -> f32 {
    if abs(x) <= FLT_EPSILON {
        return copysign(1.0, x) / FLT_EPSILON;
    }
    return 1.0 / x;
}

// Ray::new: origin, direction, per-axis safe inverse, t in [0, tmax].
fn make_ray(origin: vec3<f32>, dir: vec3<f32>, tmax: f32) -> Ray {
    return Ray(origin, dir, vec3(safe_inverse(dir.x), safe_inverse(dir.y), safe_inverse(dir.z)), tmax);
}

// Slab test (Aabb::intersect_ray): entry t = max of per-axis min(t1, t2) if the slabs overlap ahead, else infinity.
fn aabb_intersect(node: BvhNode, ray: Ray) -> f32 {
    let t1 = (node.min - ray.origin) * ray.inv_dir;
    let t2 = (node.max - ray.origin) * ray.inv_dir;
    let lo = min(t1, t2);
    let hi = max(t1, t2);
    let tmin = max(max(lo.x, lo.y), lo.z);
    let tmax = min(min(hi.x, hi.y), hi.z);
    if tmax >= tmin && tmax >= 0.0 {
        return tmin;
    }
    return inf_f32();
}

// Moller-Trumbore as obvhs writes it: e1 = v0 - v1, e2 = v2 - v0, u, v, w = 1 - u - v all sign-bit clear, t in [0, tmax].
fn triangle_intersect(tri: Triangle, ray: Ray) -> f32 {
    let e1 = tri.v0 - tri.v1;
    let e2 = tri.v2 - tri.v0;
    let n = cross3(e1, e2);
    let c = tri.v0 - ray.origin;
    let r = cross3(ray.dir, c);
    let inv_det = 1.0 / dot3(n, ray.dir);
    let u = dot3(r, e2) * inv_det;
    let v = dot3(r, e1) * inv_det;
    let w = 1.0 - u - v;
    let signs = (bitcast<u32>(u) | bitcast<u32>(v) | bitcast<u32>(w)) & 0x80000000u;
    if inv_det != 0.0 && signs == 0u {
        let t = dot3(n, c) * inv_det;
        if t >= 0.0 && t <= ray.tmax {
            return t;
        }
    }
    return inf_f32();
}

// Tests a leaf's triangles in order, the nearest so far shrinking tmax; false stops the walk (any-hit found one).
fn intersect_leaf(node: BvhNode, ray: ptr<function, Ray>, hit: ptr<function, u32>, any_hit: bool) -> bool {
    for (var p = node.first_index; p < node.first_index + node.prim_count; p++) {
        let t = triangle_intersect(triangles[p], *ray);
        if t < (*ray).tmax {
            *hit = p;
            if any_hit {
                return false;
            }
            (*ray).tmax = t;
        }
    }
    return true;
}

// Stack-based BVH2 walk (obvhs ray_traverse_dynamic): nearer child first, leaves tested on arrival. Returns the hit leaf-order triangle or NO_INDEX; ray.tmax ends at the hit t.
fn traverse(ray: ptr<function, Ray>, any_hit: bool) -> u32 {
    var hit = NO_INDEX;
    let root = nodes[0];
    // EMPTY_TREE (bvh_flat.rs): an inner node whose children would start at the root itself.
    if root.prim_count == 0u && root.first_index == 0u {
        return hit;
    }
    if aabb_intersect(root, *ray) >= (*ray).tmax {
        return hit;
    }
    if root.prim_count > 0u {
        intersect_leaf(root, ray, &hit, any_hit);
        return hit;
    }
    var stack: array<u32, STACK_SIZE>;
    var sp = 0u;
    var current = root.first_index;
    loop {
        var left = nodes[current];
        var right = nodes[current + 1u];
        var left_t = aabb_intersect(left, *ray);
        var right_t = aabb_intersect(right, *ray);
        if left_t > right_t {
            let n = left;
            left = right;
            right = n;
            let t = left_t;
            left_t = right_t;
            right_t = t;
        }
        var go_left = left_t < (*ray).tmax;
        if go_left && left.prim_count > 0u {
            if !intersect_leaf(left, ray, &hit, any_hit) {
                return hit;
            }
            go_left = false;
        }
        var go_right = right_t < (*ray).tmax;
        if go_right && right.prim_count > 0u {
            if !intersect_leaf(right, ray, &hit, any_hit) {
                return hit;
            }
            go_right = false;
        }
        if go_left && go_right {
            current = left.first_index;
            stack[min(sp, STACK_SIZE - 1u)] = right.first_index;
            sp = min(sp + 1u, STACK_SIZE);
        } else if go_left {
            current = left.first_index;
        } else if go_right {
            current = right.first_index;
        } else {
            if sp == 0u {
                return hit;
            }
            sp -= 1u;
            current = stack[sp];
        }
    }
    return hit;
}

// Accel::unoccluded: no triangle in t in [0, tmax].
fn unoccluded(origin: vec3<f32>, dir: vec3<f32>, tmax: f32) -> bool {
    var ray = make_ray(origin, dir, tmax);
    return traverse(&ray, true) == NO_INDEX;
}

// Barycentrics (b1, b2) on the triangle's plane, Moller & Trumbore: b1 = (s.p) / det, b2 = (d.q) / det, clamped into the triangle.
fn barycentrics(tri: Triangle, origin: vec3<f32>, dir: vec3<f32>) -> vec2<f32> {
    let e1 = tri.v1 - tri.v0;
    let e2 = tri.v2 - tri.v0;
    let p = cross3(dir, e2);
    let det = dot3(e1, p);
    if det == 0.0 || !is_finite(det) {
        return vec2(0.0);
    }
    let inv = 1.0 / det;
    let s = origin - tri.v0;
    let q = cross3(s, e1);
    let b1 = min_num(max_num(dot3(s, p) * inv, 0.0), 1.0);
    let b2 = min_num(max_num(dot3(dir, q) * inv, 0.0), 1.0 - b1);
    return vec2(b1, b2);
}

// Segment i with cdf[i] <= u < cdf[i + 1] of a table of len values at offset (partition_point), and u's offset in it.
fn invert_cdf(offset: u32, len: u32, u_in: f32) -> CdfPick {
    let n = len - 1u;
    let u = select(min_num(max_num(u_in, 0.0), ONE_MINUS_EPSILON), 0.0, is_nan(u_in));
    var lo = 0u;
    var hi = len;
    while lo < hi {
        let mid = (lo + hi) / 2u;
        if table[offset + mid] <= u {
            lo = mid + 1u;
        } else {
            hi = mid;
        }
    }
    let i = min(max(lo, 1u) - 1u, n - 1u);
    let width = table[offset + i + 1u] - table[offset + i];
    var du = 0.5f;
    if width > 0.0 {
        du = min_num(max_num((u - table[offset + i]) / width, 0.0), ONE_MINUS_EPSILON);
    }
    return CdfPick(i, du);
}

// AreaLights::sample: emitter index by inverting the power CDF at u.
fn sample_emitter(u: f32) -> u32 {
    return invert_cdf(params.light_cdf, params.emitter_count + 1u, u).index;
}

// Emitter e (4 words at params.emitters + 4 e in `surface`).
fn load_emitter(e: u32) -> Emitter {
    let o = params.emitters + 4u * e;
    return Emitter(surface[o], surface[o + 1u], surface_f32(o + 2u), surface_f32(o + 3u));
}

// AreaLights::pdf_area: pmf / area.
fn pdf_area(e: u32) -> f32 {
    let emitter = load_emitter(e);
    return emitter.pmf / emitter.area;
}

// Uniform point on a triangle (Turk 1990): b0 = 1 - sqrt(u0), b1 = sqrt(u0) (1 - u1), b2 = sqrt(u0) u1.
fn sample_triangle(tri: Triangle, u: vec2<f32>) -> vec3<f32> {
    let su = sqrt(max_num(u.x, 0.0));
    return tri.v0 * (1.0 - su) + tri.v1 * (su * (1.0 - u.y)) + tri.v2 * (su * u.y);
}

// glam Quat * Vec3: v (w^2 - b.b) + b 2 (v.b) + (b x v) 2 w with b = q.xyz.
fn quat_rotate(q: vec4<f32>, v: vec3<f32>) -> vec3<f32> {
    let b = q.xyz;
    let b2 = dot3(b, b);
    return v * (q.w * q.w - b2) + b * (dot3(v, b) * 2.0) + cross3(b, v) * (q.w * 2.0);
}

// Uniform direction on the sphere: z = 1 - 2 u.x, phi = 2 pi u.y.
fn uniform_sphere(u: vec2<f32>) -> vec3<f32> {
    let z = 1.0 - 2.0 * u.x;
    let r = sqrt(max_num(1.0 - z * z, 0.0));
    let phi = TAU * u.y;
    return vec3(r * cos(phi), r * sin(phi), z);
}

// Equirectangular (u, v) of unit d: u = atan2(d.z, d.x) / (2 pi) in [0, 1), v = acos(d.y) / pi.
fn direction_to_uv(d: vec3<f32>) -> vec2<f32> {
    let phi = atan2(d.z, d.x);
    var u = phi / TAU;
    if phi < 0.0 {
        u = phi / TAU + 1.0;
    }
    return vec2(select(u, 0.0, u >= 1.0), acos(min_num(max_num(d.y, -1.0), 1.0)) * FRAC_1_PI);
}

// d = (sin t cos p, cos t, sin t sin p) with p = 2 pi u, t = pi v.
fn uv_to_direction(uv: vec2<f32>) -> vec3<f32> {
    let t = PI * uv.y;
    let p = TAU * uv.x;
    return vec3(sin(t) * cos(p), cos(t), sin(t) * sin(p));
}

// Distribution2D::cell_pdf: func[cell] / marginal integral.
fn env_cell_pdf(col: u32, row: u32) -> f32 {
    return table[params.env_func + row * params.env_width + col] / params.env_marginal_integral;
}

// map.rs solid_angle_pdf of the cell's density: p(u, v) / (2 pi^2 sin theta), 0 at the poles.
fn env_solid_angle_pdf(col: u32, row: u32, sin_theta: f32) -> f32 {
    if sin_theta <= 0.0 {
        return 0.0;
    }
    return env_cell_pdf(col, row) / (2.0 * PI * PI * sin_theta);
}

// Column and row of the texel seen along unit map-space d.
fn env_cell(d: vec3<f32>) -> vec2<u32> {
    let uv = direction_to_uv(d);
    let col = min(u32(uv.x * f32(params.env_width)), params.env_width - 1u);
    let row = min(u32(uv.y * f32(params.env_height)), params.env_height - 1u);
    return vec2(col, row);
}

// Environment::radiance: the constant, or scale times the nearest texel.
fn env_radiance(dir: vec3<f32>) -> vec3<f32> {
    if params.env_kind == ENV_CONSTANT {
        return params.env_radiance;
    }
    let c = env_cell(quat_rotate(params.env_to_map, dir));
    return env_texel(c.x, c.y);
}

// EnvMap::texel: scale times the RGB of texel (col, row).
fn env_texel(col: u32, row: u32) -> vec3<f32> {
    let i = params.env_texels + 4u * (row * params.env_width + col);
    return params.env_scale * vec3(table[i], table[i + 1u], table[i + 2u]);
}

// Environment::pdf: 1 / (4 pi), or the map's solid-angle density.
fn env_pdf(dir: vec3<f32>) -> f32 {
    if params.env_kind == ENV_CONSTANT {
        return 0.25 * FRAC_1_PI;
    }
    let d = quat_rotate(params.env_to_map, dir);
    let c = env_cell(d);
    return env_solid_angle_pdf(c.x, c.y, sqrt(max_num(1.0 - d.y * d.y, 0.0)));
}

// A light sample of the environment: direction, solid-angle pdf and the radiance along it.
struct EnvSample {
    wi: vec3<f32>,
    pdf: f32,
    radiance: vec3<f32>,
}

// Environment::sample_with_radiance: uniform sphere, or row then column of the map's Distribution2D and that texel.
fn env_sample(u: vec2<f32>) -> EnvSample {
    if params.env_kind == ENV_CONSTANT {
        return EnvSample(uniform_sphere(u), 0.25 * FRAC_1_PI, params.env_radiance);
    }
    let w = params.env_width;
    let h = params.env_height;
    let m = invert_cdf(params.env_marginal_cdf, h + 1u, u.y);
    let row = m.index;
    let y = min_num((f32(row) + m.du) / f32(h), ONE_MINUS_EPSILON);
    let c = invert_cdf(params.env_conditional_cdf + row * (w + 1u), w + 1u, u.x);
    let col = c.index;
    let x = min_num((f32(col) + c.du) / f32(w), ONE_MINUS_EPSILON);
    let d = uv_to_direction(vec2(x, y));
    let pdf = env_solid_angle_pdf(col, row, sin(PI * y));
    return EnvSample(quat_rotate(params.env_to_world, d), pdf, env_texel(col, row));
}

// ---------------------------------------------------------------------------------------------
// Punctual lights (ggx-scene punctual.rs), read from `surface`
// ---------------------------------------------------------------------------------------------

// Punctual light i (16 words at params.punctual_lights + 16 i).
fn load_punctual(i: u32) -> PunctualLight {
    let o = params.punctual_lights + 16u * i;
    return PunctualLight(
        surface_vec3(o),
        surface[o + 3u],
        surface_vec3(o + 4u),
        surface_f32(o + 7u),
        surface_vec3(o + 8u),
        surface_f32(o + 11u),
        surface_f32(o + 12u),
        array<u32, 3>(0u, 0u, 0u),
    );
}

// PunctualLight::incident: I window(d) spot(w) / d^2 toward -w at distance d (window clamp(1 - (d / range)^4, 0, 1),
// spot clamp(cos scale + offset, 0, 1)^2), 0 unless finite; a directional light's irradiance as is.
fn punctual_incident(l: PunctualLight, w: vec3<f32>, d: f32) -> vec3<f32> {
    if l.kind == PUNCTUAL_DIRECTIONAL {
        return l.intensity;
    }
    var atten = 1.0 / (d * d);
    if l.range > 0.0 {
        let r = d / l.range;
        let r2 = r * r;
        atten *= min_num(max_num(1.0 - r2 * r2, 0.0), 1.0);
    }
    if l.kind == PUNCTUAL_SPOT {
        let cd = dot3(l.direction, -w);
        let a = min_num(max_num(cd * l.spot_scale + l.spot_offset, 0.0), 1.0);
        atten *= a * a;
    }
    let out = l.intensity * atten;
    return select(vec3(0.0), out, is_finite3(out));
}

// ---------------------------------------------------------------------------------------------
// Texture coordinates and textures (ggx-scene mesh.rs, texture.rs), read from `surface`
// ---------------------------------------------------------------------------------------------

// Word i of `surface` as f32.
fn surface_f32(i: u32) -> f32 {
    return bitcast<f32>(surface[i]);
}

// Words i, i + 1 of `surface` as a vec2<f32>.
fn surface_vec2(i: u32) -> vec2<f32> {
    return vec2(surface_f32(i), surface_f32(i + 1u));
}

// Words i..i + 3 of `surface` as a vec3<f32>.
fn surface_vec3(i: u32) -> vec3<f32> {
    return vec3(surface_f32(i), surface_f32(i + 1u), surface_f32(i + 2u));
}

// The TextureRef at word o of `surface` (8 words: texture, flags, transform).
fn load_texture_ref(o: u32) -> TextureRef {
    return TextureRef(surface[o], surface[o + 1u], surface_vec3(o + 2u), surface_vec3(o + 5u));
}

// TextureRef::is_some: a texture is set.
fn texture_ref_is_some(r: TextureRef) -> bool {
    return r.texture != NO_INDEX;
}

// TextureRef::apply: s = m0 u + m1 v + m2, t = m3 u + m4 v + m5.
fn texture_ref_apply(r: TextureRef, uv: vec2<f32>) -> vec2<f32> {
    return vec2(r.s.x * uv.x + r.s.y * uv.y + r.s.z, r.t.x * uv.x + r.t.y * uv.y + r.t.z);
}

// TriangleUvs::interpolate of record k: b0 uv0 + b1 uv1 + b2 uv2, b0 = 1 - b1 - b2.
fn interpolate_uv(k: u32, b1: f32, b2: f32) -> vec2<f32> {
    let o = params.uvs + 8u * k;
    let uv0 = vec2(surface_f32(o), surface_f32(o + 1u));
    let uv1 = vec2(surface_f32(o + 2u), surface_f32(o + 3u));
    let uv2 = vec2(surface_f32(o + 4u), surface_f32(o + 5u));
    return (1.0 - b1 - b2) * uv0 + b1 * uv1 + b2 * uv2;
}

// SceneData::uv_at: the triangle's interpolated texture coordinates, 0 without any.
fn uv_at(tri: Triangle, b1: f32, b2: f32) -> vec2<f32> {
    if tri.normals >= params.uv_count {
        return vec2(0.0);
    }
    return interpolate_uv(tri.normals, b1, b2);
}

// Word i of TextureSet::words, 0 past its end (the table is the last section of `surface`).
fn texture_word(i: u32) -> u32 {
    let j = params.texture_words + i;
    if i > j || j >= arrayLength(&surface) {
        return 0u;
    }
    return surface[j];
}

// Wrap::from_bits: 1 clamp to edge, 2 mirrored repeat, 0 and 3 repeat.
fn wrap_bits(bits: u32) -> u32 {
    return bits & 3u;
}

// wrap_coord: [0, 1) for repeat, [0, 1] for clamp, mirrored for mirrored repeat; NaN, inf -> 0.
fn wrap_coord(s_in: f32, wrap: u32) -> f32 {
    let s = select(0.0, s_in, is_finite(s_in));
    if wrap == WRAP_CLAMP_TO_EDGE {
        return min_num(max_num(s, 0.0), 1.0);
    } else if wrap == WRAP_MIRRORED_REPEAT {
        let p = s * 0.5;
        let f = 2.0 * (p - floor(p));
        return select(f, 2.0 - f, f > 1.0);
    }
    return s - floor(s);
}

// texel_index: floor of x >= 0 (NaN -> 0), at most n - 1 (Rust's saturating `as u32` then `min`).
fn texel_index(x: f32, n: u32) -> u32 {
    return min(u32(min_num(max_num(x, 0.0), f32(n - 1u))), n - 1u);
}

// neighbour: the texel a bilinear tap at i reads: wrapped (repeat), reflected (mirrored), clamped.
fn neighbour(i: f32, n: u32, wrap: u32) -> u32 {
    let nf = f32(n);
    var j = i;
    if wrap == WRAP_MIRRORED_REPEAT {
        if i < 0.0 {
            j = -1.0 - i;
        } else if i >= nf {
            j = 2.0 * nf - 1.0 - i;
        }
    } else if wrap != WRAP_CLAMP_TO_EDGE {
        if i < 0.0 {
            j = i + nf;
        } else if i >= nf {
            j = i - nf;
        }
    }
    return texel_index(j, n);
}

// TextureSet::texel: linear RGBA of texel (x, y); float texels as stored (0 unless all finite),
// 8-bit channels i / 255 (the upload's table of the CPU's values), R, G, B through the sRGB table.
fn texel(info: TextureInfo, x: u32, y: u32, srgb: bool) -> vec4<f32> {
    let i = y * info.width + x;
    if (info.flags & TEXTURE_FLOAT) != 0u {
        let o = info.offset + 4u * i;
        let v = vec4(
            bitcast<f32>(texture_word(o)),
            bitcast<f32>(texture_word(o + 1u)),
            bitcast<f32>(texture_word(o + 2u)),
            bitcast<f32>(texture_word(o + 3u)),
        );
        return select(vec4(0.0), v, is_finite3(v.xyz) && is_finite(v.w));
    }
    let w = texture_word(info.offset + i);
    let c = vec4((w >> 0u) & 255u, (w >> 8u) & 255u, (w >> 16u) & 255u, w >> 24u);
    let a = surface_f32(params.texture_unorm + c.w);
    if srgb {
        let lut = params.texture_words;
        return vec4(surface_f32(lut + c.x), surface_f32(lut + c.y), surface_f32(lut + c.z), a);
    }
    let u = params.texture_unorm;
    return vec4(surface_f32(u + c.x), surface_f32(u + c.y), surface_f32(u + c.z), a);
}

// TextureSet::sample: linear RGBA of r at uv: transform, wrap, then bilinear (texel centres at
// half-integers) or nearest; 0 for a missing texture.
fn texture_sample(r: TextureRef, uv: vec2<f32>) -> vec4<f32> {
    if r.texture >= params.texture_count {
        return vec4(0.0);
    }
    let ib = params.texture_infos + 4u * r.texture;
    let info = TextureInfo(surface[ib], surface[ib + 1u], surface[ib + 2u], surface[ib + 3u]);
    let st = texture_ref_apply(r, uv);
    let srgb = (r.flags & REF_SRGB) != 0u;
    let wrap_s = wrap_bits(info.flags >> TEXTURE_WRAP_S_SHIFT);
    let wrap_t = wrap_bits(info.flags >> TEXTURE_WRAP_T_SHIFT);
    let s = wrap_coord(st.x, wrap_s);
    let t = wrap_coord(st.y, wrap_t);
    let w = info.width;
    let h = info.height;
    if (info.flags & TEXTURE_NEAREST) != 0u {
        return texel(info, texel_index(s * f32(w), w), texel_index(t * f32(h), h), srgb);
    }
    let x = s * f32(w) - 0.5;
    let y = t * f32(h) - 0.5;
    let x0 = floor(x);
    let y0 = floor(y);
    let fx = x - x0;
    let fy = y - y0;
    let xa = neighbour(x0, w, wrap_s);
    let xb = neighbour(x0 + 1.0, w, wrap_s);
    let ya = neighbour(y0, h, wrap_t);
    let yb = neighbour(y0 + 1.0, h, wrap_t);
    let top = texel(info, xa, ya, srgb) * (1.0 - fx) + texel(info, xb, ya, srgb) * fx;
    let bottom = texel(info, xa, yb, srgb) * (1.0 - fx) + texel(info, xb, yb, srgb) * fx;
    return top * (1.0 - fy) + bottom * fy;
}

// TextureSet::sample_channel: the slot's channel (0 R, 1 G, 2 B, 3 A) of texture_sample.
fn texture_sample_channel(r: TextureRef, uv: vec2<f32>) -> f32 {
    return texture_sample(r, uv)[(r.flags >> REF_CHANNEL_SHIFT) & 3u];
}
