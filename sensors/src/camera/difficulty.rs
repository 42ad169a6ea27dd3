//! How hard a frame is for a visual method, like the LiDAR scans' degeneracy: the share of
//! pixels the light reaches, the mean brightness, the corners a feature tracker would find,
//! and the motion blur.
//!
//! - **lit share**: pixels whose expected signal is at least five times its noise (shot and
//!   read noise at the frame's exposure), of those the lens sees;
//! - **mean brightness**: the written image's mean grey value, 0 to 255 (a colour image
//!   converted as OpenCV's `cvtColor` converts it, by the same integer weights);
//! - **keypoints**: FAST-9 corners at a threshold of 20 (Rosten and Drummond; the detector
//!   ORB and ORB-SLAM use), counted without non-maximum suppression, 3 pixels in from the
//!   border, exactly as OpenCV's `FastFeatureDetector(20, false)` counts them;
//! - **motion blur**: how far, in pixels, the points a grid of pixels sees move across the
//!   image during the exposure (mean over the grid), from the trajectory's poses at the
//!   exposure's start and end.

use serde::Serialize;

use super::render::Shot;

/// One camera's difficulty in one frame.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Difficulty {
    /// Share of the pixels the lens sees that the light reaches (expected signal at least five
    /// times its noise), 0 to 1.
    pub lit_share: f64,
    /// Mean grey value of the image, 0 to 255.
    pub mean_brightness: f64,
    /// FAST-9 corners at threshold 20.
    pub keypoints: u64,
    /// Mean image motion during the exposure, pixels.
    pub motion_blur_px: f64,
}

/// The grey value of an RGB pixel as OpenCV's `cvtColor(..., RGB2GRAY)` computes it for
/// 8-bit images: fixed-point weights 4899, 9617 and 1868 over 2^14, rounded.
#[inline]
pub fn grey(rgb: [u8; 3]) -> u8 {
    ((u32::from(rgb[0]) * 4899 + u32::from(rgb[1]) * 9617 + u32::from(rgb[2]) * 1868 + (1 << 13))
        >> 14) as u8
}

/// An image (`channels` 3 or 1 a pixel) as grey values.
pub fn to_grey(image: &[u8], channels: usize, out: &mut Vec<u8>) {
    out.clear();
    if channels == 1 {
        out.extend_from_slice(image);
    } else {
        out.extend(image.chunks_exact(3).map(|p| grey([p[0], p[1], p[2]])));
    }
}

/// The FAST circle's 16 pixels, `(dx, dy)`, in OpenCV's order.
const CIRCLE: [(isize, isize); 16] = [
    (0, 3),
    (1, 3),
    (2, 2),
    (3, 1),
    (3, 0),
    (3, -1),
    (2, -2),
    (1, -3),
    (0, -3),
    (-1, -3),
    (-2, -2),
    (-3, -1),
    (-3, 0),
    (-3, 1),
    (-2, 2),
    (-1, 3),
];

/// FAST-9 corners of a grey image at threshold `t`, without non-maximum suppression: pixels
/// 3 or more from the border with 9 contiguous circle pixels all brighter than it by more than
/// `t`, or all darker by more than `t`.
pub fn fast9(grey: &[u8], width: usize, height: usize, t: u8) -> u64 {
    use rayon::prelude::*;
    if width < 7 || height < 7 {
        return 0;
    }
    let t = i16::from(t);
    (3..height - 3)
        .into_par_iter()
        .map(|y| {
            let mut n = 0u64;
            for x in 3..width - 3 {
                let v = i16::from(grey[y * width + x]);
                let mut states = [0u8; 16];
                let (mut any_bright, mut any_dark) = (0, 0);
                for (k, (dx, dy)) in CIRCLE.iter().enumerate() {
                    let q = i16::from(
                        grey[(y as isize + dy) as usize * width + (x as isize + dx) as usize],
                    );
                    states[k] = if q - v > t {
                        any_bright += 1;
                        2
                    } else if q - v < -t {
                        any_dark += 1;
                        1
                    } else {
                        0
                    };
                }
                let corner = |s: u8, count: usize| {
                    if count < 9 {
                        return false;
                    }
                    let mut run = 0;
                    for k in 0..16 + 9 {
                        if states[k % 16] == s {
                            run += 1;
                            if run >= 9 {
                                return true;
                            }
                        } else {
                            run = 0;
                        }
                    }
                    false
                };
                if corner(2, any_bright) || corner(1, any_dark) {
                    n += 1;
                }
            }
            n
        })
        .sum()
}

/// The share of the lens's pixels whose expected signal at `exposure_s` seconds is at least
/// five times its noise (`read_noise_e` of read noise).
pub fn lit_share(shot: &Shot, exposure_s: f64, read_noise_e: f64) -> f64 {
    let (mut seen, mut lit) = (0u64, 0u64);
    let r2 = read_noise_e * read_noise_e;
    for s in &shot.signal {
        if s[0] < 0.0 {
            continue;
        }
        seen += 1;
        let e = f64::from(s[0] + s[1] + s[2]) / 3.0 * exposure_s;
        if e >= 5.0 * (e + r2).sqrt() {
            lit += 1;
        }
    }
    if seen == 0 {
        0.0
    } else {
        lit as f64 / seen as f64
    }
}

/// The mean of grey values over the pixels `seen` marks (all when it is `None`).
pub fn mean_brightness(grey: &[u8], shot: &Shot) -> f64 {
    let (mut sum, mut n) = (0u64, 0u64);
    for (g, s) in grey.iter().zip(&shot.signal) {
        if s[0] >= 0.0 {
            sum += u64::from(*g);
            n += 1;
        }
    }
    if n == 0 { 0.0 } else { sum as f64 / n as f64 }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fast_finds_a_bright_square_s_corners_and_nothing_on_flat_ground() {
        let (w, h) = (40, 40);
        let mut img = vec![50u8; w * h];
        assert_eq!(fast9(&img, w, h, 20), 0);
        for y in 15..25 {
            for x in 15..25 {
                img[y * w + x] = 200;
            }
        }
        // Corners are found near the square's four corners, not along its edges' middles.
        let n = fast9(&img, w, h, 20);
        assert!(n >= 4, "{n}");
        // A pixel on an edge's middle: only 7 of 16 circle pixels differ.
        let mut edge = vec![50u8; w * h];
        for y in 0..h {
            for x in 20..w {
                edge[y * w + x] = 200;
            }
        }
        assert_eq!(fast9(&edge, w, h, 20), 0);
    }

    #[test]
    fn grey_is_opencv_s_weights() {
        assert_eq!(grey([255, 255, 255]), 255);
        assert_eq!(grey([255, 0, 0]), 76);
        assert_eq!(grey([0, 255, 0]), 150);
        assert_eq!(grey([0, 0, 255]), 29);
    }
}
