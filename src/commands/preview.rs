//! `subtgraph preview`.

use std::path::PathBuf;

use subtgraph::app::preview::{Light, View, parse_size};
use subtgraph::app::{Error, PreviewRequest};

/// `preview`'s arguments.
#[derive(clap::Args)]
pub struct Args {
    /// A world folder generated with a tile set.
    world: PathBuf,
    /// The PNG to write.
    #[arg(long)]
    out: PathBuf,
    /// Picture size, WIDTHxHEIGHT pixels.
    #[arg(long, default_value = "1280x800")]
    size: String,
    /// Draw the few tiles around the start (or --at NODE) instead of the whole world.
    #[arg(long, conflicts_with = "inside")]
    close_up: bool,
    /// Draw what a robot sees from inside the passage at the start (or --at NODE), 1.5 m
    /// above its floor, looking along its first passage.
    #[arg(long)]
    inside: bool,
    /// The graph node (an id of topology.json) a --close-up or --inside picture is taken at.
    #[arg(long, value_name = "NODE")]
    at: Option<usize>,
    /// lamp: a light just above the camera that falls off with distance, as a robot's lamp
    /// shows a passage (the default with --inside); sun: a fixed light from above, the same
    /// at every distance (the default from outside, where a lamp at the far camera lights
    /// every face alike).
    #[arg(long, value_name = "lamp|sun")]
    light: Option<String>,
}

/// Draws the picture and prints its size and triangles drawn.
pub fn run(a: Args) -> Result<(), Error> {
    let (width, height) = parse_size(&a.size)?;
    let view = if a.inside {
        View::Inside
    } else if a.close_up {
        View::CloseUp
    } else {
        View::Whole
    };
    let light = match a.light {
        Some(name) => name.parse()?,
        None if a.inside => Light::Lamp,
        None => Light::Sun,
    };
    let drawn = PreviewRequest {
        world: a.world,
        out: a.out.clone(),
        width,
        height,
        view,
        light,
        at: a.at,
    }
    .run()?;
    super::print(&format!(
        "wrote {} ({width} x {height}, {} triangles drawn)\n",
        a.out.display(),
        drawn.triangles
    ));
    Ok(())
}
