//! The cameras' rasterised first hits (sensors/src/camera/raster.rs) against the core's ray
//! caster on a real cave: the same triangle and the same distance for every pixel but the
//! rare one on an edge two triangles share (the same distance, either triangle), checked
//! twice: for every pixel of whole frames against the renderer's own ray path (the camera
//! without its raster grid), and for a few hundred pixels against `RayCaster::cast` called
//! directly with the pixel's ray.

use subtgraph::core::Pipeline;
use subtgraph::core::export::{Exporter, MemoryWriter};
use subtgraph_sensors::camera::light::Rig;
use subtgraph_sensors::camera::presets;
use subtgraph_sensors::camera::render::{Renderer, Shot};
use subtgraph_sensors::camera::scene::CameraScene;
use subtgraph_sensors::frames::mul;
use subtgraph_sensors::platform::Platform;
use subtgraph_sensors::trajectory::Trajectory;

use crate::common::{json_point, small_cave_pipeline};

/// What one frame's two first-hit passes disagree on.
#[derive(Default, Debug)]
struct Differences {
    pixels: usize,
    /// Pixels whose triangles differ at the same distance (an edge shared by two).
    on_edges: usize,
    /// Pixels whose distances differ by more than a micrometre: a triangle missed.
    missed: usize,
    worst_m: f64,
}

fn compare(a: Option<(u32, f32)>, b: Option<(u32, f32)>, d: &mut Differences) {
    d.pixels += 1;
    match (a, b) {
        (None, None) => {}
        (Some((ta, da)), Some((tb, db))) => {
            let off = f64::from((da - db).abs());
            d.worst_m = d.worst_m.max(off);
            if off > 1e-6 * f64::from(da.max(1.0)) {
                d.missed += 1;
            } else if ta != tb {
                d.on_edges += 1;
            }
        }
        _ => {
            d.missed += 1;
            d.worst_m = f64::INFINITY;
        }
    }
}

#[test]
fn rasterised_first_hits_are_the_ray_casters_on_a_cave() {
    let dir = tempfile::tempdir().unwrap();
    let path = small_cave_pipeline(dir.path(), 1, "");
    let pipeline = Pipeline::parse(&std::fs::read_to_string(&path).unwrap(), "cave").unwrap();
    let world = subtgraph::core::generate(&pipeline, &subtgraph::registry()).unwrap();
    let survey = subtgraph::survey::WorldSurvey::new(&world).unwrap();
    let mut out = MemoryWriter::default();
    subtgraph::exporters::GraphFiles
        .export(&world, &survey, &mut out)
        .unwrap();
    let graph: serde_json::Value =
        serde_json::from_slice(out.get("ground_truth/graph.json").unwrap()).unwrap();
    let scene = CameraScene::of(&world, &[]).unwrap();
    let model = presets::stereo();
    let platform = Platform::named("ground").unwrap();
    let rig = Rig::on(&platform, &model, None, 0.0);

    // Views from the middle of each of the first corridors, looking along them.
    let mut views = Vec::new();
    for e in graph["edges"].as_array().unwrap() {
        let line: Vec<[f64; 3]> = e["polyline"]
            .as_array()
            .unwrap()
            .iter()
            .map(json_point)
            .collect();
        if line.len() < 3 || views.len() == 4 {
            continue;
        }
        let m = line.len() / 2;
        let (p, q) = (line[m], line[m + 1]);
        let yaw = (q[1] - p[1]).atan2(q[0] - p[0]);
        views.push([p[0], p[1], p[2] + 0.2, yaw, 0.0, 0.0]);
    }
    assert_eq!(views.len(), 4, "the cave has four corridors to look along");

    let mut whole = Differences::default();
    let mut direct = Differences::default();
    let mut seen = 0usize;
    for v in views {
        let trajectory = Trajectory::new(1.0, vec![v; 6]);
        let mut renderer = Renderer::new(&scene, &trajectory, &rig, &model, false);
        for c in 0..model.cameras.len() {
            assert!(
                renderer.pixels[c].grid.is_some(),
                "a pinhole camera is rasterised"
            );
        }
        let mut drawn = Shot::default();
        renderer.render(0, 0.0, 0.01, &mut drawn);
        let pose = renderer.camera_pose(0, 0.0);
        let px = &renderer.pixels[0];
        let n = px.width * px.height;
        // A few hundred pixels against the caster itself.
        for k in (0..n).step_by(997) {
            let ray = px.rays[k].map(f64::from);
            let cast = scene
                .caster
                .cast(pose.translation, mul(&pose.rotation, ray), 500.0)
                .map(|h| (h.triangle, h.t as f32));
            compare(drawn.first_hit(k), cast, &mut direct);
        }
        // Every pixel against the renderer's ray path.
        renderer.pixels[0].grid = None;
        let mut cast = Shot::default();
        renderer.render(0, 0.0, 0.01, &mut cast);
        for k in 0..n {
            seen += usize::from(cast.first_hit(k).is_some());
            compare(drawn.first_hit(k), cast.first_hit(k), &mut whole);
        }
        // Labels and depth follow the triangle.
        let off = (0..n)
            .filter(|&k| drawn.first_hit(k).map(|h| h.0) == cast.first_hit(k).map(|h| h.0))
            .filter(|&k| drawn.depth[k] != cast.depth[k] || drawn.class[k] != cast.class[k])
            .count();
        assert_eq!(
            off, 0,
            "depth or class differs where the triangle is the same"
        );
    }
    eprintln!("raster vs cast: every pixel {whole:?}; sampled against RayCaster::cast {direct:?}");
    assert!(
        seen > whole.pixels * 9 / 10,
        "the views see the cave: {seen} of {}",
        whole.pixels
    );
    assert!(direct.pixels >= 1200, "{direct:?}");
    assert_eq!(direct.missed, 0, "{direct:?}");
    assert_eq!(whole.missed, 0, "{whole:?}");
    // A ray exactly through a shared edge is rare.
    assert!(whole.on_edges * 1000 < whole.pixels, "{whole:?}");
}
