//! The air between a camera and what it sees, when `sense --conditions` puts dust, fog or mist
//! there: each pixel's light dimmed on its way and the robot's own lamps scattered back into
//! the lens, the haze that grows with the lamps' power (issue 39 item 3).
//!
//! The physics is [`crate::conditions::camera::camera_ray`]'s single scattering, through the
//! media spans the LiDAR's rays cross ([`Active::spans`], the same placed clouds and banks, the
//! same raised dust at the same instant): the light the lamps put on the surface crosses the
//! air twice (`T_L`), the ambient light once (`T`), and the lamps add `L_b` along the ray. The
//! particles' extinction and backscatter are the LiDAR's (particles much larger than the
//! wavelength scatter the same at 865 nm and in visible light, extinction efficiency 2), and
//! the haze is white: the lamps' light is, and such particles scatter every colour alike.
//!
//! A lamp's intensity along a pixel's ray is what it puts a metre out on that ray
//! ([`PlacedLamp::at`] times the distance squared), so the haze is brightest where the beams
//! cross the view and fades at its edges, as a real robot's does. The lamps sit a few
//! centimetres from the lens; the beam's overlap with the view starts
//! [`crate::conditions::camera::OVERLAP_M`] out. Shadows in the air (a beam cut by a rock
//! before the pixel's surface) are not drawn.
//!
//! A ray no medium crosses keeps its light to the bit: `--conditions none`, or a bank the
//! camera does not look through, renders what clear air does.

use subtgraph_core::vec3::V3;

use super::light::PlacedLamp;
use crate::conditions::camera::{Lamp, camera_ray};
use crate::conditions::medium::Span;
use crate::conditions::{Active, Frame};

/// The air a renderer looks through: the conditions, and the state they are in for the row
/// being drawn.
pub struct Air<'s, 'a> {
    /// The conditions.
    pub active: &'s Active<'a>,
    /// Their state at the row's instant (the platform's dust cloud, the drops).
    pub frame: Frame,
    /// The media along the current ray (reused).
    spans: Vec<Span>,
}

impl<'s, 'a> Air<'s, 'a> {
    /// The air of `active` at time `t` about a camera at `at`.
    pub fn at(active: &'s Active<'a>, t: f64, at: V3) -> Air<'s, 'a> {
        Air {
            active,
            frame: active.frame(t, at),
            spans: Vec::new(),
        }
    }

    /// The light a pixel receives along the unit ray `dir` from `origin` to a surface `t`
    /// metres away, which sends `total` candela per square metre towards it, `ambient` of it
    /// lit by the ambient light and the rest by `lamps`.
    pub fn seen(
        &mut self,
        origin: V3,
        dir: V3,
        t: f64,
        total: [f64; 3],
        ambient: [f64; 3],
        lamps: &[PlacedLamp],
    ) -> [f64; 3] {
        self.active
            .spans(&self.frame, origin, dir, t, &mut self.spans);
        if self.spans.is_empty() {
            return total;
        }
        let metre_out = [origin[0] + dir[0], origin[1] + dir[1], origin[2] + dir[2]];
        let intensity: f64 = lamps
            .iter()
            .map(|l| {
                let (lux, _, d) = l.at(metre_out);
                lux * d * d
            })
            .sum();
        let s = camera_ray(
            &self.spans,
            t,
            &Lamp {
                intensity_w_sr: intensity,
            },
        );
        [0, 1, 2].map(|c| {
            let lamp_lit = (total[c] - ambient[c]).max(0.0);
            ambient[c] * s.transmittance + lamp_lit * s.lamp_transmittance + s.backscatter
        })
    }
}
