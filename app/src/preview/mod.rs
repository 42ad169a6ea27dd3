//! `subtgraph preview`: a shaded perspective picture of a world's mesh, drawn on the CPU (no
//! GPU, no display): from above and to the south-west (the whole world, or a close-up of the
//! tiles around a node), or from inside a passage, where a robot's camera would be.
//!
//! Triangles are kept only when they face the camera from the passage side, so from outside
//! the ceilings nearest the camera drop out and the picture shows the floors and far walls of
//! every passage: a cutaway of the network at a glance. From inside, triangles are clipped at
//! the camera, so walls right beside it are drawn too.
//!
//! Two lights ([`Light`]). The sun, fixed and high, lights a face by its angle alone and suits
//! the outside views: a lamp at a camera many tiles away lights every face nearly alike, as a
//! flash photograph does. The lamp, a point light just above the camera that falls off with
//! distance, is how a robot sees a passage: faces turned to it bright, grazing ones dark, near
//! rock brighter than far rock, so relief, slopes and chambers read from the shading.
//!
//! Each pixel keeps its nearest triangle (depth as 1/z, interpolated on screen) and is shaded
//! once afterwards, in one thread and in a fixed order: the same world and options give the
//! same PNG bytes.
//!
//! [`PreviewRequest::run`] takes these steps: the node a close-up or inside view is taken at
//! (`place.rs`), the mesh (`scene.rs`), the view framed (cropped around the node, or the eye
//! put on its floor), the camera and lamp placed (`camera.rs`), the triangles rasterised and
//! the pixels shaded (`draw.rs`), and the picture written.

mod camera;
mod draw;
mod place;
mod scene;

use std::path::{Path, PathBuf};

use subtgraph_core::vec3::{V3, dot, sub};

use crate::Error;
use camera::{Camera, outside_camera};
use place::{Place, pitch_of, place_of};
use scene::{Scene, crop, floor_under, read_scene, scene_centre};

/// Where the light comes from (`--light`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Light {
    /// A point light just above the camera whose light falls off with distance, as a robot's
    /// lamp shows a passage: each face lit by how squarely it faces the lamp (Lambert, faces
    /// turned away stay dark), near surfaces brighter than far ones, so relief, slopes and
    /// chambers read from their shading; a little ambient light keeps nothing pure black.
    Lamp,
    /// A fixed light from high in the south-east, the same at every distance (the pictures
    /// before lamps): every face lit by the angle it makes with that light, either side.
    Sun,
}

impl std::str::FromStr for Light {
    type Err = Error;
    fn from_str(s: &str) -> Result<Self, Error> {
        match s {
            "lamp" => Ok(Light::Lamp),
            "sun" => Ok(Light::Sun),
            other => Err(Error::Usage(format!(
                "--light must be lamp (a light at the camera that falls off with distance, the default) or sun (a fixed light from above, the same everywhere), not '{}'",
                subtgraph_core::error::excerpt(other)
            ))),
        }
    }
}

/// What the camera looks at.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum View {
    /// The whole world from above and to the south-west.
    Whole,
    /// The tiles within 3.5 tile pitches of a node (the start unless `at`), from above and to
    /// the south-west.
    CloseUp,
    /// From inside the passage at a node (the start unless `at`), 1.5 m above its floor, looking
    /// along its first passage: what a robot's camera sees there.
    Inside,
}

/// What `preview` is asked to draw.
#[derive(Clone, Debug)]
pub struct PreviewRequest {
    /// A world folder generated with a tile set.
    pub world: PathBuf,
    /// The PNG to write.
    pub out: PathBuf,
    /// Picture width in pixels.
    pub width: usize,
    /// Picture height in pixels.
    pub height: usize,
    /// What the camera looks at.
    pub view: View,
    /// Where the light comes from.
    pub light: Light,
    /// The graph node a close-up or inside view is taken at (`None`: the start).
    pub at: Option<usize>,
}

/// A picture drawn.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Drawn {
    /// Triangles drawn.
    pub triangles: usize,
}

/// Parses a picture size, `WIDTHxHEIGHT`, 16 to 8192 pixels each.
pub fn parse_size(text: &str) -> Result<(usize, usize), Error> {
    text.split_once('x')
        .and_then(|(w, h)| Some((w.parse::<usize>().ok()?, h.parse::<usize>().ok()?)))
        .filter(|&(w, h)| (16..=8192).contains(&w) && (16..=8192).contains(&h))
        .ok_or_else(|| {
            Error::Usage(
                "--size must be WIDTHxHEIGHT, 16 to 8192 pixels each, like 1280x800".into(),
            )
        })
}

/// Light that reaches every face whatever its facing or distance, as a share of full light.
const AMBIENT: f64 = 0.12;
/// The lamp's reach `d0` as a share of the tile pitch: its light falls off as
/// `1 / (1 + (d / d0)^2)` at `d` metres, half at `d0`. Pictures are exposed for the nearest
/// lit surface (full light there, if it faces the lamp squarely).
const LAMP_REACH: f64 = 0.5;
/// The inside view's camera height above the floor, metres (a ground robot's mast camera).
const EYE_HEIGHT: f64 = 1.5;
/// How far above the camera the lamp sits, metres (inside view).
const LAMP_ABOVE: f64 = 0.3;

/// Where the camera stands and looks from, and the tile pitch the lamp's reach scales with.
struct Framed {
    scene: Scene,
    pitch: f64,
    /// Inside a passage: the eye and the direction it looks.
    inside_eye: Option<(V3, V3)>,
}

impl PreviewRequest {
    /// Draws `world/mesh/world.obj` into a PNG at `out` (replacing only a picture `preview`
    /// drew before).
    pub fn run(&self) -> Result<Drawn, Error> {
        let (width, height) = (self.width, self.height);
        if self.view == View::Whole && self.at.is_some() {
            return Err(Error::Usage(
                "--at NODE picks where a --close-up or --inside picture is taken; add one of them"
                    .into(),
            ));
        }
        check_out(&self.out, &self.world)?;
        // The node first: a wrong --at is refused before the mesh is read.
        let place = match self.view {
            View::Whole => None,
            View::CloseUp | View::Inside => Some(place_of(&self.world, self.at)?),
        };
        let scene = read_scene(&self.world)?;
        let framed = self.frame(scene, place.as_ref())?;
        let (camera, lamp, near) = self.camera(&framed);
        let frame = draw::rasterise(&framed.scene, &camera, near, width, height);
        let image = draw::shade(
            &framed.scene,
            &frame,
            &camera,
            self.light,
            lamp,
            framed.pitch,
        );
        let png = draw::encode(&image, width, height)
            .map_err(|e| Error::Input(format!("encoding the picture: {e}")))?;
        write_picture(&self.out, &self.world, &png)?;
        Ok(Drawn {
            triangles: frame.drawn,
        })
    }

    /// The scene as the view sees it: the whole mesh, the tiles around the node (close-up),
    /// or the whole mesh with the eye on the node's floor (inside).
    fn frame(&self, scene: Scene, place: Option<&Place>) -> Result<Framed, Error> {
        let Some(place) = place else {
            return Ok(Framed {
                pitch: pitch_of(&self.world),
                scene,
                inside_eye: None,
            });
        };
        if self.view == View::CloseUp {
            let scene = crop(
                scene,
                place.cell_centre,
                3.5 * place.pitch,
                0.3 * place.level,
                0.9 * place.level,
            );
            if scene.triangles.is_empty() {
                return Err(Error::Input("nothing to draw around the tile".into()));
            }
            return Ok(Framed {
                scene,
                pitch: place.pitch,
                inside_eye: None,
            });
        }
        let level = place.level;
        let floor = match place.floor {
            Some(f) => f,
            None => {
                let c = place.cell_centre;
                let z = floor_under(&scene, c, 0.5 * level, 0.9 * level).ok_or_else(|| {
                    Error::Input(format!(
                        "no floor under the centre of node {}'s tile; make the world with ground truth (`subtgraph generate --format obj,ground-truth`), whose graph gives each node's floor",
                        self.at.map_or("start".to_owned(), |n| n.to_string())
                    ))
                })?;
                [c[0], c[1], z]
            }
        };
        let along = place.along.unwrap_or([1.0, 0.0, 0.0]);
        // A little downward, as a robot's camera is tilted to see the ground ahead.
        let tilt = 8f64.to_radians();
        let forward = [along[0] * tilt.cos(), along[1] * tilt.cos(), -tilt.sin()];
        Ok(Framed {
            scene,
            pitch: place.pitch,
            inside_eye: Some(([floor[0], floor[1], floor[2] + EYE_HEIGHT], forward)),
        })
    }

    /// The camera, the lamp and the near plane for a framed scene.
    fn camera(&self, framed: &Framed) -> (Camera, V3, f64) {
        let (width, height) = (self.width, self.height);
        let camera = if let Some((eye, forward)) = framed.inside_eye {
            let (forward, right, up) = Camera::looking(forward);
            // 90 degrees across.
            Camera {
                eye,
                right,
                up,
                forward,
                focal: 0.5 * width as f64,
                centre: [0.0, 0.0],
                half: [0.5 * width as f64, 0.5 * height as f64],
            }
        } else {
            outside_camera(&framed.scene, self.view, width, height)
        };
        // The lamp: just above the camera (inside: a robot's lamp; outside: a lamp carried
        // with the viewer, a tenth of the way to the picture's centre above it, so faces
        // turned a little up read lighter than walls).
        let lamp = if framed.inside_eye.is_some() {
            [camera.eye[0], camera.eye[1], camera.eye[2] + LAMP_ABOVE]
        } else {
            let lift =
                0.1 * dot(sub(camera.eye, scene_centre(&framed.scene)), camera.forward).abs();
            [0, 1, 2].map(|k| camera.eye[k] + lift * camera.up[k])
        };
        let near = if framed.inside_eye.is_some() {
            0.05
        } else {
            1e-6
        };
        (camera, lamp, near)
    }
}

/// The PNG `Software` text our pictures carry: how `preview` knows a file is one it drew.
const SOFTWARE: &str = "subtgraph preview";

/// Refuses an `--out` that is not a file name, lies inside the world folder being read, or
/// holds a file `preview` did not draw: before anything is read, and again before writing.
fn check_out(out: &Path, world: &Path) -> Result<(), Error> {
    if out.file_name().is_none() {
        return Err(Error::Usage("--out must name a file, like cave.png".into()));
    }
    if let (Ok(world), Some(Ok(parent))) = (
        world.canonicalize(),
        out.parent()
            .map(|p| {
                if p.as_os_str().is_empty() {
                    Path::new(".")
                } else {
                    p
                }
            })
            .map(Path::canonicalize),
    ) && parent.starts_with(&world)
    {
        return Err(Error::Usage(format!(
            "--out {} is inside the world folder {} this command reads (a file there is not one the world's list names); choose another --out",
            out.display(),
            world.display()
        )));
    }
    if out.exists() {
        let ours = std::fs::File::open(out)
            .ok()
            .and_then(|f| {
                png::Decoder::new(std::io::BufReader::new(f))
                    .read_info()
                    .ok()
            })
            .is_some_and(|r| {
                r.info()
                    .uncompressed_latin1_text
                    .iter()
                    .any(|t| t.keyword == "Software" && t.text == SOFTWARE)
            });
        if !ours {
            return Err(Error::Usage(format!(
                "{} exists and is not a picture subtgraph preview drew; choose another --out (it is never overwritten)",
                out.display()
            )));
        }
    }
    Ok(())
}

/// Writes the picture through a temporary file and a rename, replacing only a picture
/// `preview` drew before: any other file at `out` is the user's and is refused.
fn write_picture(out: &Path, world: &Path, bytes: &[u8]) -> Result<(), Error> {
    check_out(out, world)?;
    let name = out
        .file_name()
        .ok_or_else(|| Error::Usage("--out must name a file, like cave.png".into()))?
        .to_string_lossy();
    let tmp = out.with_file_name(format!(".{name}.partial-{}", std::process::id()));
    std::fs::write(&tmp, bytes)
        .and_then(|()| std::fs::rename(&tmp, out))
        .map_err(|e| {
            let _ = std::fs::remove_file(&tmp);
            Error::Input(format!(
                "writing {}: {e}{}",
                out.display(),
                subtgraph_core::export::io_hint(&e)
            ))
        })
}

#[cfg(test)]
mod tests {
    use super::*;
    use camera::clip_near;

    /// A triangle crossing the near plane keeps the part in front of it: one vertex behind
    /// gives a quadrilateral, two behind a smaller triangle, every corner on or before the
    /// plane, and the crossing points on the triangle's edges.
    #[test]
    fn clipping_at_the_camera_keeps_the_part_in_front() {
        let near = 0.05;
        let quad = clip_near([[0.0, 0.0, -1.0], [1.0, 0.0, 1.0], [0.0, 1.0, 1.0]], near);
        assert_eq!(quad.len(), 4);
        assert!(quad.iter().all(|p| p[2] >= near - 1e-12));
        // The edge from (0,0,-1) to (1,0,1) crosses z = near at x = (near + 1) / 2.
        assert!(
            quad.iter()
                .any(|p| (p[0] - (near + 1.0) / 2.0).abs() < 1e-12 && p[1] == 0.0)
        );
        let tri = clip_near([[0.0, 0.0, 2.0], [1.0, 0.0, -1.0], [0.0, 1.0, -1.0]], near);
        assert_eq!(tri.len(), 3);
        assert!(tri.iter().all(|p| p[2] >= near - 1e-12));
        assert!(clip_near([[0.0, 0.0, -1.0], [1.0, 0.0, -1.0], [0.0, 1.0, 0.0]], near).is_empty());
    }

    /// The light names `--light` takes, and a refusal that names both.
    #[test]
    fn lights_by_name() {
        assert_eq!("lamp".parse::<Light>().unwrap(), Light::Lamp);
        assert_eq!("sun".parse::<Light>().unwrap(), Light::Sun);
        let e = "Lamp".parse::<Light>().unwrap_err().to_string();
        assert!(
            e.contains("lamp") && e.contains("sun") && e.contains("'Lamp'"),
            "{e}"
        );
    }
}
