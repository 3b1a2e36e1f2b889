//! The packet's shared steps give each path the bits it computes alone.

use super::*;
use crate::{AccelKind, PACKET_RAYS};
use ggx_core::SequenceKind;
use std::path::Path;

/// A plastic floor, rough and smooth (delta) conductors, an area light and a procedural sky
/// that next-event estimation samples; roulette from the first bounce on.
const SCENE: &str = r#"
[camera]
position = [0, 1.2, 4]
look_at = [0, 0.4, 0]
fov_y = 45.0
resolution = [24, 16]

[integrator]
max_depth = 4
russian_roulette = 1

[environment]
type = "procedural"
preset = "sky"
resolution = [64, 32]
rotation = 30

[materials.floor]
type = "plastic"
roughness = 0.5
ior = 1.5
albedo = [0.45, 0.45, 0.42]

[materials.gold]
type = "conductor"
roughness = 0.3
preset = "gold"

[materials.mirror]
type = "conductor"
roughness = 0.0
preset = "silver"

[materials.lamp]
type = "emissive"
radiance = [4, 4, 4]

[[shapes]]
type = "rectangle"
material = "floor"
transform = { rotate = [-90, 0, 0], scale = 8 }

[[shapes]]
type = "sphere"
material = "gold"
center = [-0.6, 0.5, 0]
radius = 0.5

[[shapes]]
type = "sphere"
material = "mirror"
center = [0.6, 0.5, 0]
radius = 0.5

[[shapes]]
type = "rectangle"
material = "lamp"
transform = { translate = [0, 3, 1], rotate = [90, 0, 0], scale = 0.5 }
"#;

/// A path whose first bounce was drawn ahead with its packet's (`draw_first_bounces`)
/// returns the bits of the same path drawing it itself, over every pixel and 16 samples,
/// and the environment's light samples were drawn ahead for some of them.
#[test]
fn first_bounces_drawn_ahead_are_the_bounces_drawn_in_the_path() {
    let scene = ggx_scene::parse_scene(SCENE, "test.toml", Path::new(".")).unwrap_or_else(|e| panic!("{e}"));
    let data = SceneData::new(&scene, AccelKind::default());
    assert!(data.environment_is_light && !data.lights.is_empty());
    let [w, h] = data.camera.resolution;
    let mut counters = Counters::default();
    let (mut ahead, mut env_ahead) = (0, 0);
    for pixel in 0..w * h {
        let mut seeds = core::array::from_fn(|_| PixelSeeds::new(0));
        let seed = SampleStream::new(SequenceKind::Sobol, 5, pixel, 0).seed;
        seeds[0] = PixelSeeds::new(seed);
        let mut streams = [SampleStream { kind: 0, seed: 0, sample_index: 0, dimension: 0 }; PACKET_RAYS];
        let mut rays = [(Vec3::ZERO, Vec3::ZERO); PACKET_RAYS];
        for (s, (stream, ray)) in streams.iter_mut().zip(&mut rays).enumerate() {
            *stream = SampleStream::new(SequenceKind::Sobol, 5, pixel, s as u32);
            let jitter = stream.next_2d_with(&mut seeds[0]);
            let xy = Vec2::new((pixel % w) as f32, (pixel / w) as f32) + jitter;
            *ray = data.ray_generator.generate_ray(xy);
        }
        let hits = rays.map(|(o, d)| data.accel.closest(o, d, f32::INFINITY));
        let in_path = streams;
        let mut firsts = [None; PACKET_RAYS];
        let slots = [0; PACKET_RAYS];
        assert!(draw_first_bounces::<true, true>(&data, &hits, &mut streams, &slots, &mut seeds, &mut firsts));
        ahead += firsts.iter().flatten().count();
        env_ahead += firsts.iter().flatten().filter(|f| f.env_sample.is_some()).count();
        for k in 0..PACKET_RAYS {
            let (o, d) = rays[k];
            let mut stream = in_path[k];
            let want = trace::<true, true, true, true, false>(
                &data,
                o,
                d,
                hits[k],
                None,
                &mut stream,
                &mut seeds[0],
                &mut counters,
            );
            let got = trace::<true, true, true, true, false>(
                &data,
                o,
                d,
                hits[k],
                firsts[k],
                &mut streams[k],
                &mut seeds[0],
                &mut counters,
            );
            let bits = |t: &Traced| {
                (t.radiance.to_array().map(f32::to_bits), t.escape.map(|e| (e.dir, e.beta, e.prev_pdf.to_bits())))
            };
            assert_eq!(bits(&got), bits(&want), "pixel {pixel} sample {k}");
            assert_eq!(stream, streams[k], "pixel {pixel} sample {k}: the dimensions consumed");
        }
    }
    // Paths that hit the delta mirror or nothing are not drawn ahead; the others are, and
    // those that pick the environment (half of them) carry its light sample.
    let paths = (w * h) as usize * PACKET_RAYS;
    assert!(ahead > paths / 2 && ahead < paths, "{ahead} of {paths} drawn ahead");
    assert!(env_ahead > ahead / 3 && env_ahead < ahead, "{env_ahead} environment samples of {ahead}");
}
