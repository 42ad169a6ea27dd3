//! Ranges in a pipeline file: a number, or `[low, high]` drawn uniformly from the world's seed.
//!
//! Their own module (re-exported by `config`) so that sections defined elsewhere, like
//! `[artifacts]`, can use them without a module cycle with `config`.

use std::fmt;

use serde::de::{self, Deserializer, Visitor};
use serde::{Deserialize, Serialize, Serializer};

use crate::rng::WorldRng;

/// A whole number, or `[low, high]` drawn uniformly.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum IntRange {
    /// Always this value.
    Fixed(u32),
    /// Uniform in `low..=high`.
    Between(u32, u32),
}

/// A number, or `[low, high]` drawn uniformly.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum FloatRange {
    /// Always this value.
    Fixed(f64),
    /// Uniform in `[low, high]`.
    Between(f64, f64),
}

impl IntRange {
    /// Draws a value.
    pub fn draw(self, rng: &mut WorldRng) -> u32 {
        match self {
            IntRange::Fixed(v) => v,
            IntRange::Between(lo, hi) => rng.int_in(i64::from(lo), i64::from(hi)) as u32,
        }
    }
    /// The largest value it can take.
    pub fn max(self) -> u32 {
        match self {
            IntRange::Fixed(v) | IntRange::Between(_, v) => v,
        }
    }
}

impl FloatRange {
    /// Draws a value.
    pub fn draw(self, rng: &mut WorldRng) -> f64 {
        match self {
            FloatRange::Fixed(v) => v,
            FloatRange::Between(lo, hi) => rng.float_in(lo, hi),
        }
    }
}

impl Serialize for IntRange {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        match *self {
            IntRange::Fixed(v) => s.serialize_u32(v),
            IntRange::Between(a, b) => [a, b].serialize(s),
        }
    }
}

impl Serialize for FloatRange {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        match *self {
            FloatRange::Fixed(v) => s.serialize_f64(v),
            FloatRange::Between(a, b) => [a, b].serialize(s),
        }
    }
}

struct RangeVisitor<const INT: bool>;

impl<'de, const INT: bool> Visitor<'de> for RangeVisitor<INT> {
    type Value = (f64, Option<f64>);

    fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
        if INT {
            f.write_str("a whole number >= 0 or [low, high]")
        } else {
            f.write_str("a number >= 0 or [low, high]")
        }
    }

    fn visit_i64<E: de::Error>(self, v: i64) -> Result<Self::Value, E> {
        Ok((v as f64, None))
    }
    fn visit_u64<E: de::Error>(self, v: u64) -> Result<Self::Value, E> {
        Ok((v as f64, None))
    }
    fn visit_f64<E: de::Error>(self, v: f64) -> Result<Self::Value, E> {
        if INT {
            return Err(E::custom(format!(
                "expected a whole number or [low, high], found {v}"
            )));
        }
        Ok((v, None))
    }
    fn visit_seq<A: de::SeqAccess<'de>>(self, mut seq: A) -> Result<Self::Value, A::Error> {
        use de::Error;
        let bad = || A::Error::custom("a range is [low, high]: two numbers with low <= high");
        let lo = seq.next_element::<RangeNumber>()?.ok_or_else(bad)?.0;
        let hi = seq.next_element::<RangeNumber>()?.ok_or_else(bad)?.0;
        if seq.next_element::<RangeNumber>()?.is_some() || lo > hi {
            return Err(bad());
        }
        if INT && (lo.fract() != 0.0 || hi.fract() != 0.0) {
            return Err(A::Error::custom("expected whole numbers in [low, high]"));
        }
        Ok((lo, Some(hi)))
    }
}

struct RangeNumber(f64);
impl<'de> Deserialize<'de> for RangeNumber {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct V;
        impl Visitor<'_> for V {
            type Value = f64;
            fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                f.write_str("a number")
            }
            fn visit_i64<E: de::Error>(self, v: i64) -> Result<f64, E> {
                Ok(v as f64)
            }
            fn visit_u64<E: de::Error>(self, v: u64) -> Result<f64, E> {
                Ok(v as f64)
            }
            fn visit_f64<E: de::Error>(self, v: f64) -> Result<f64, E> {
                Ok(v)
            }
        }
        d.deserialize_any(V).map(RangeNumber)
    }
}

fn check_non_negative<E: de::Error>((lo, hi): (f64, Option<f64>)) -> Result<(), E> {
    if lo < 0.0 || hi.is_some_and(|h| h < 0.0) || !lo.is_finite() {
        return Err(E::custom(
            "must be >= 0: a number, or [low, high] with 0 <= low <= high",
        ));
    }
    Ok(())
}

impl<'de> Deserialize<'de> for IntRange {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let v = d.deserialize_any(RangeVisitor::<true>)?;
        check_non_negative::<D::Error>(v)?;
        if v.0 > f64::from(u32::MAX) || v.1.is_some_and(|h| h > 1000.0) {
            return Err(de::Error::custom(
                "too large: a count is at most 4294967295, and a [low, high] range's high end \
                 at most 1000",
            ));
        }
        Ok(match v {
            (x, None) => IntRange::Fixed(x as u32),
            (a, Some(b)) => IntRange::Between(a as u32, b as u32),
        })
    }
}

impl<'de> Deserialize<'de> for FloatRange {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let v = d.deserialize_any(RangeVisitor::<false>)?;
        check_non_negative::<D::Error>(v)?;
        Ok(match v {
            (x, None) => FloatRange::Fixed(x),
            (a, Some(b)) => FloatRange::Between(a, b),
        })
    }
}
