use serde::{Deserialize, Serialize};

use crate::contact::{Contact, Penetration};
use crate::geometry::Vec2;
use crate::shape::{Pose, ShapeError, Superellipse};
use crate::subdivision::{Precision, PrecisionError};

/// The project's one JSON form of a placed shape:
/// `{"center": [x, y], "angle": radians, "semi_axes": [sx, sy], "exponents": [ex, ey]}`.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ShapeJson {
    pub center: [f64; 2],
    #[serde(default)]
    pub angle: f64,
    pub semi_axes: [f64; 2],
    pub exponents: [f64; 2],
}

impl ShapeJson {
    /// The validated shape and pose.
    pub fn to_shape(&self) -> Result<(Superellipse, Pose), ShapeError> {
        Ok((
            Superellipse::new(self.semi_axes, self.exponents)?,
            Pose::new(Vec2::from(self.center), self.angle)?,
        ))
    }

    pub fn from_shape(shape: &Superellipse, pose: &Pose) -> Self {
        ShapeJson {
            center: pose.center().to_array(),
            angle: pose.angle(),
            semi_axes: shape.semi_axes().to_array(),
            exponents: shape.exponents(),
        }
    }
}

impl std::str::FromStr for ShapeJson {
    type Err = String;

    /// The command line's short form `X,Y,ANGLE,SX,SY,EX,EY` (centre, angle in radians,
    /// semi-axes, exponents), or the JSON object. The numbers are not checked here: see
    /// [`ShapeJson::to_shape`].
    fn from_str(s: &str) -> Result<Self, String> {
        if s.trim_start().starts_with('{') {
            return serde_json::from_str::<ShapeJson>(s)
                .map_err(|e| format!("not a shape object: {e}"));
        }
        let v: Vec<f64> = s
            .split(',')
            .map(|x| {
                x.trim()
                    .parse::<f64>()
                    .map_err(|_| format!("`{}` is not a number", x.trim()))
            })
            .collect::<Result<_, _>>()?;
        let [x, y, angle, sx, sy, ex, ey] = v[..] else {
            return Err(format!(
                "expected 7 numbers X,Y,ANGLE,SX,SY,EX,EY, got {}",
                v.len()
            ));
        };
        Ok(ShapeJson {
            center: [x, y],
            angle,
            semi_axes: [sx, sy],
            exponents: [ex, ey],
        })
    }
}

/// A shape in a batch line: the JSON object, or the string `"X,Y,ANGLE,SX,SY,EX,EY"` (the
/// command line's SHAPE).
fn shape_or_text<'de, D: serde::Deserializer<'de>>(d: D) -> Result<ShapeJson, D::Error> {
    struct V;
    impl<'de> serde::de::Visitor<'de> for V {
        type Value = ShapeJson;
        fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
            f.write_str("a shape: {\"center\": ..., ...} or \"X,Y,ANGLE,SX,SY,EX,EY\"")
        }
        fn visit_str<E: serde::de::Error>(self, s: &str) -> Result<ShapeJson, E> {
            s.parse().map_err(E::custom)
        }
        fn visit_map<A: serde::de::MapAccess<'de>>(self, map: A) -> Result<ShapeJson, A::Error> {
            ShapeJson::deserialize(serde::de::value::MapAccessDeserializer::new(map))
        }
    }
    d.deserialize_any(V)
}

/// One line of `supergrain contact --batch`: `{"a": SHAPE, "b": SHAPE}`, optionally with
/// `"depth"` and `"eps"`; each SHAPE an object or the string `"X,Y,ANGLE,SX,SY,EX,EY"`.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ContactQuery {
    #[serde(deserialize_with = "shape_or_text")]
    pub a: ShapeJson,
    #[serde(deserialize_with = "shape_or_text")]
    pub b: ShapeJson,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub depth: Option<u32>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub eps: Option<f64>,
}

/// Why a query cannot be answered.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum QueryError {
    #[error("shape a: {0}")]
    A(ShapeError),
    #[error("shape b: {0}")]
    B(ShapeError),
    #[error(transparent)]
    Precision(#[from] PrecisionError),
}

impl ContactQuery {
    /// The validated shapes, poses and precision; missing `depth`/`eps` come from `defaults`.
    #[allow(clippy::type_complexity)]
    pub fn resolve(
        &self,
        defaults: &Precision,
    ) -> Result<((Superellipse, Pose), (Superellipse, Pose), Precision), QueryError> {
        let a = self.a.to_shape().map_err(QueryError::A)?;
        let b = self.b.to_shape().map_err(QueryError::B)?;
        let precision = Precision::new(
            self.depth.unwrap_or(defaults.depth()),
            self.eps.unwrap_or(defaults.eps()),
        )?;
        Ok((a, b, precision))
    }
}

/// The answer to a [`ContactQuery`]:
/// `{"overlap", "a_deepest", "b_deepest", "a_push", "b_push", "cells", "contacts"}`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ContactAnswer {
    pub overlap: bool,
    pub a_deepest: Option<[f64; 2]>,
    pub b_deepest: Option<[f64; 2]>,
    pub a_push: Option<[f64; 2]>,
    pub b_push: Option<[f64; 2]>,
    pub cells: u32,
    /// Every overlap region, the one above first ([`crate::contact::overlap_regions`]); empty
    /// when apart.
    #[serde(default)]
    pub contacts: Vec<RegionAnswer>,
}

/// One overlap region of a [`ContactAnswer`]: its deepest points and pushes.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct RegionAnswer {
    pub a_deepest: [f64; 2],
    pub b_deepest: [f64; 2],
    pub a_push: [f64; 2],
    pub b_push: [f64; 2],
}

impl From<&Penetration> for RegionAnswer {
    fn from(p: &Penetration) -> Self {
        RegionAnswer {
            a_deepest: p.a_deepest.to_array(),
            b_deepest: p.b_deepest.to_array(),
            a_push: p.a_push.to_array(),
            b_push: p.b_push.to_array(),
        }
    }
}

impl From<&Contact> for ContactAnswer {
    /// The answer with its one region (see [`ContactAnswer::with_regions`] for all of them).
    fn from(c: &Contact) -> Self {
        let p = c.penetration;
        ContactAnswer {
            overlap: c.overlap(),
            a_deepest: p.map(|p| p.a_deepest.to_array()),
            b_deepest: p.map(|p| p.b_deepest.to_array()),
            a_push: p.map(|p| p.a_push.to_array()),
            b_push: p.map(|p| p.b_push.to_array()),
            cells: c.cells,
            contacts: p.iter().map(RegionAnswer::from).collect(),
        }
    }
}

impl ContactAnswer {
    /// The answer listing `regions` (the first being the contact's own).
    pub fn with_regions(mut self, regions: &[Penetration]) -> Self {
        self.contacts = regions.iter().map(RegionAnswer::from).collect();
        self
    }
}
