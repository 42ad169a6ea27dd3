//! Runs a mission on a preset (with artifacts), printing what happens.
use std::time::Instant;

fn cpu() -> f64 {
    let t = std::fs::read_to_string("/proc/self/stat").unwrap();
    let f: Vec<&str> = t.split_whitespace().collect();
    (f[13].parse::<f64>().unwrap() + f[14].parse::<f64>().unwrap()) / 100.0
}

fn main() {
    let a: Vec<String> = std::env::args().collect();
    let preset = a.get(1).cloned().unwrap_or("cave".into());
    let robots: usize = a.get(2).map_or(1, |s| s.parse().unwrap());
    let duration: f64 = a.get(3).map_or(120.0, |s| s.parse().unwrap());
    let seed: u64 = a.get(4).map_or(1, |s| s.parse().unwrap());
    let policy = a.get(5).cloned().unwrap_or("frontier".into());
    let text =
        std::fs::read_to_string(format!("examples/{preset}.toml")).unwrap() + "\n[artifacts]\n";
    let mut p = subtgraph_core::Pipeline::parse(&text, "x").unwrap();
    p.world.seed = seed;
    let mut r = subtgraph_core::Registry::with_core_shapes();
    subtgraph_descriptors::register(&mut r).unwrap();
    subtgraph_tilesets::register(&mut r).unwrap();
    let t = Instant::now();
    let world = subtgraph_core::generate(&p, &r).unwrap();
    let survey = subtgraph_survey::WorldSurvey::new(&world).unwrap();
    let site = subtgraph_explore::Site::of(&survey).unwrap();
    eprintln!("setup {:.1} s", t.elapsed().as_secs_f64());
    let options = subtgraph_explore::Options {
        robots,
        body: subtgraph_explore::body::Body::named("ground").unwrap(),
        lidar: subtgraph_explore::lidar::Lidar::named(
            "vlp-16",
            std::env::var("COLS").ok().map(|c| c.parse().unwrap()),
            |_| None,
        )
        .unwrap(),
        duration,
        control_hz: 10.0,
        map_voxel: 0.5,
        policy: subtgraph_explore::Policy::named(&policy).unwrap(),
        breadcrumbs: 6,
        radio: Default::default(),
        detector: Default::default(),
        seed,
        noiseless: false,
        max_map_bytes: 8 << 30,
    };
    let mut m = subtgraph_explore::Mission::new(site, options, None).unwrap();
    let t = Instant::now();
    let c0 = cpu();
    let total = m.total_steps();
    let mut last = [0u64; 4];
    while m.steps < total {
        m.step();
        if std::env::var("VERBOSE").is_ok() {
            for r in &m.robots {
                if r.refusals != last {
                    eprintln!(
                        "t {:.1} robot {} at {:?} refusals {:?} mode {:?} goal {:?}",
                        m.time,
                        r.id,
                        r.state.position.map(|v| (v * 100.0).round() / 100.0),
                        r.refusals,
                        r.planner.mode,
                        r.planner.goal.map(|g| g.map(|v| (v * 10.0).round() / 10.0))
                    );
                    last = r.refusals;
                }
            }
        }
        if m.steps % 600 == 0 {
            let d: f64 = m.robots.iter().map(|r| r.odometer).sum();
            let det = (0..m.site.artifacts.len())
                .filter(|&i| m.robots.iter().any(|r| r.detected[i]))
                .count();
            eprintln!(
                "t {:.0}: {:.0} m, {} det of {}, free {}, crumbs {}, modes {:?}",
                m.time,
                d,
                det,
                m.site.artifacts.len(),
                m.robots.iter().map(|r| r.map.free).max().unwrap(),
                m.crumbs.len(),
                m.robots.iter().map(|r| r.planner.mode).collect::<Vec<_>>()
            );
        }
    }
    if let Ok(path) = std::env::var("PPM") {
        let r = &m.robots[0];
        let space = subtgraph_explore::planner::space::Space::around(
            &r.map,
            &m.options.body,
            r.state.position,
            &r.blocked,
        );
        let g = r.map.grid;
        let c = g
            .voxel_of([
                r.state.position[0],
                r.state.position[1],
                r.state.position[2] + 0.25,
            ])
            .unwrap();
        let half = 100i32;
        let mut img = Vec::new();
        for y in (-half..half).rev() {
            for x in -half..half {
                let mut col = [128u8, 128, 128];
                let mut best = 9;
                for dz in [0i32, 1, -1, 2, -2] {
                    let v = [c[0] + x, c[1] + y, c[2] + dz];
                    let p = subtgraph_explore::planner::space::Place(v);
                    let rank;
                    let colour;
                    if space.is_place(p) && space.is_frontier(p) {
                        rank = 0;
                        colour = [0, 0, 255];
                    } else if space.is_place(p) {
                        rank = 1;
                        colour = [0, 200, 0];
                    } else if dz >= 0 && r.map.is_occupied(v) {
                        rank = 2;
                        colour = [0, 0, 0];
                    } else if r.map.is_free(v) {
                        rank = 3;
                        colour = [255, 255, 255];
                    } else {
                        continue;
                    }
                    if rank < best {
                        best = rank;
                        col = colour;
                    }
                }
                if x == 0 && y == 0 {
                    col = [255, 0, 0];
                }
                if let Some(gl) = r.planner.goal {
                    if let Some(gv) = g.voxel_of(gl) {
                        if gv[0] == c[0] + x && gv[1] == c[1] + y {
                            col = [255, 0, 255];
                        }
                    }
                }
                img.extend_from_slice(&col);
            }
        }
        for x in (-60..0).step_by(3) {
            let mut line = String::new();
            for dz in -4..=3 {
                let v = [c[0] + x, c[1], c[2] + dz];
                let ch = match r.map.get(v) {
                    subtgraph_explore::map::Voxel::Unknown => '?',
                    subtgraph_explore::map::Voxel::Free => '.',
                    subtgraph_explore::map::Voxel::Occupied => '#',
                };
                line.push(ch);
            }
            eprintln!("x {x:4}: {line}");
        }
        let mut out = format!("P6\n{} {}\n255\n", 2 * half, 2 * half).into_bytes();
        out.extend(img);
        std::fs::write(path, out).unwrap();
    }
    if let Ok(path) = std::env::var("WORLDPPM") {
        let map = m.union_map();
        let g = map.grid;
        let px = 4; // voxels per pixel
        let (w, h) = (g.n[0] / px, g.n[1] / px);
        let mut img = vec![[128u8, 128, 128]; w * h];
        for v in map.voxels(subtgraph_explore::map::Voxel::Free) {
            let (x, y) = (v[0] as usize / px, v[1] as usize / px);
            if x < w && y < h {
                img[(h - 1 - y) * w + x] = [255, 255, 255];
            }
        }
        let put = |img: &mut Vec<[u8; 3]>, p: [f64; 3], c: [u8; 3], r: i64| {
            let x = ((p[0] - g.origin[0]) / g.voxel) as i64 / px as i64;
            let y = ((p[1] - g.origin[1]) / g.voxel) as i64 / px as i64;
            for dy in -r..=r {
                for dx in -r..=r {
                    let (xx, yy) = (x + dx, y + dy);
                    if xx >= 0 && yy >= 0 && (xx as usize) < w && (yy as usize) < h {
                        img[(h - 1 - yy as usize) * w + xx as usize] = c;
                    }
                }
            }
        };
        for (i, r) in m.robots.iter().enumerate() {
            let c = [[255u8, 0, 0], [0, 160, 0], [0, 0, 255]][i % 3];
            for s in r.trajectory.iter().step_by(5) {
                put(&mut img, s.position, c, 0);
            }
        }
        for (i, a) in m.site.artifacts.iter().enumerate() {
            let seen = m.robots.iter().any(|r| r.detected[i]);
            put(
                &mut img,
                a.centre,
                if seen { [0, 255, 0] } else { [255, 0, 255] },
                2,
            );
        }
        put(&mut img, m.site.base, [0, 0, 0], 3);
        // the whole world's free space, faintly: every surface of the collision caster? skip
        let mut out = format!("P6\n{w} {h}\n255\n").into_bytes();
        for p in img {
            out.extend_from_slice(&p);
        }
        std::fs::write(path, out).unwrap();
    }
    if std::env::var("ARTDEBUG").is_ok() {
        for (i, a) in m.site.artifacts.iter().enumerate() {
            let mut best = (f64::MAX, [0.0; 3]);
            for r in &m.robots {
                for s in &r.trajectory {
                    let d = ((s.position[0] - a.centre[0]).powi(2)
                        + (s.position[1] - a.centre[1]).powi(2)
                        + (s.position[2] - a.centre[2]).powi(2))
                    .sqrt();
                    if d < best.0 {
                        best = (d, s.position);
                    }
                }
            }
            let eye = [best.1[0], best.1[1], best.1[2] + 0.6];
            let vis = m.options.detector.in_view(&m.site.collision, eye, a.centre);
            let seen = m.robots.iter().any(|r| r.detected[i]);
            eprintln!(
                "artifact {i} {:?} at {:?}: nearest {:.1} m, in view from there {vis}, detected {seen}",
                a.class,
                a.centre.map(|v| v.round()),
                best.0
            );
        }
    }
    if std::env::var("FLOOR").is_ok() {
        let p = m.robots[0].state.position;
        eprintln!("robot at {:?} yaw {:.2}", p, m.robots[0].state.yaw);
        for j in (-8..=8).rev() {
            let mut line = String::new();
            for i in -8..=8 {
                let (x, y) = (p[0] + 0.1 * i as f64, p[1] + 0.1 * j as f64);
                let top = p[2] + 0.55;
                let z = m
                    .site
                    .collision
                    .cast([x, y, top], [0.0, 0.0, -1.0], 2.0)
                    .map(|h| top - h.t);
                line.push_str(&match z {
                    Some(z) => format!("{:5.0}", (z - p[2]) * 100.0),
                    None => "  ---".into(),
                });
            }
            eprintln!("{line}");
        }
    }
    let wall = t.elapsed().as_secs_f64();
    let c = cpu() - c0;
    eprintln!(
        "{duration} s simulated in {wall:.1} s wall, {c:.1} s CPU: {:.0}x real time per CPU second",
        duration / c
    );
    for r in &m.robots {
        eprintln!(
            "robot {}: {:.0} m, refusals {:?}, reports {}, mode {:?}",
            r.id,
            r.odometer,
            r.refusals,
            r.reports.len(),
            r.planner.mode
        );
    }
}
