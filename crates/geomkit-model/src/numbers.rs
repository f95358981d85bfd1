//! Numbers, point lists and nets as they stand in model files: finite f64 only, points of one
//! dimension, nets of one row length, read straight into flat row-major buffers (no vector
//! per point), with errors at the element's JSON path.

use serde::de::{self, DeserializeSeed, SeqAccess, Visitor};
use serde::ser::{SerializeSeq, Serializer};
use serde::{Deserialize, Deserializer, Serialize};
use std::fmt;

/// A finite JSON number.
struct Finite(f64);

impl<'de> Deserialize<'de> for Finite {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        d.deserialize_any(FiniteVisitor)
    }
}

struct FiniteVisitor;

impl Visitor<'_> for FiniteVisitor {
    type Value = Finite;
    fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str("a finite number")
    }
    fn visit_f64<E: de::Error>(self, x: f64) -> Result<Finite, E> {
        if x.is_finite() {
            Ok(Finite(x))
        } else {
            Err(E::custom(format!("is {x}, which is not a finite f64")))
        }
    }
    fn visit_i64<E: de::Error>(self, x: i64) -> Result<Finite, E> {
        Ok(Finite(x as f64))
    }
    fn visit_u64<E: de::Error>(self, x: u64) -> Result<Finite, E> {
        Ok(Finite(x as f64))
    }
    fn visit_str<E: de::Error>(self, s: &str) -> Result<Finite, E> {
        Err(E::custom(format!(
            "is the string {}; numbers must be finite JSON numbers",
            serde_json::Value::String(s.to_string())
        )))
    }
}

/// "1 point", "3 points".
pub(crate) fn count(n: usize, noun: &str) -> String {
    if n == 1 {
        format!("1 {noun}")
    } else {
        format!("{n} {noun}s")
    }
}

/// `deserialize_with` of a list of finite numbers.
pub(crate) fn numbers<'de, D: Deserializer<'de>>(d: D) -> Result<Vec<f64>, D::Error> {
    Ok(Vec::<Finite>::deserialize(d)?
        .into_iter()
        .map(|x| x.0)
        .collect())
}

/// `deserialize_with` of an optional list of finite numbers (`null` = absent).
pub(crate) fn optional_numbers<'de, D: Deserializer<'de>>(
    d: D,
) -> Result<Option<Vec<f64>>, D::Error> {
    Ok(Option::<Vec<Finite>>::deserialize(d)?.map(|v| v.into_iter().map(|x| x.0).collect()))
}

/// `deserialize_with` of an optional list of rows of finite numbers (`null` = absent).
pub(crate) fn optional_number_rows<'de, D: Deserializer<'de>>(
    d: D,
) -> Result<Option<Vec<Vec<f64>>>, D::Error> {
    Ok(Option::<Vec<Vec<Finite>>>::deserialize(d)?.map(|v| {
        v.into_iter()
            .map(|r| r.into_iter().map(|x| x.0).collect())
            .collect()
    }))
}

/// `deserialize_with` of one finite number.
pub(crate) fn number<'de, D: Deserializer<'de>>(d: D) -> Result<f64, D::Error> {
    Ok(Finite::deserialize(d)?.0)
}

/// `deserialize_with` of an interval `[a, b]` of finite numbers.
pub(crate) fn interval<'de, D: Deserializer<'de>>(d: D) -> Result<[f64; 2], D::Error> {
    let [a, b] = <[Finite; 2]>::deserialize(d)?;
    Ok([a.0, b.0])
}

/// `deserialize_with` of optional intervals `[[a, b], ...]`.
pub(crate) fn optional_intervals<'de, D: Deserializer<'de>>(
    d: D,
) -> Result<Option<Vec<[f64; 2]>>, D::Error> {
    Ok(Option::<Vec<[Finite; 2]>>::deserialize(d)?
        .map(|v| v.into_iter().map(|[a, b]| [a.0, b.0]).collect()))
}

/// Points of one dimension, row-major: point k is `flat[k * dim .. (k + 1) * dim]`.
///
/// In a file: `[[x, y], [x, y], ...]`; every point has the dimension of the first and at
/// least one coordinate (an error names the point: `points[3] has 2 coordinates but the
/// first point has 3`).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Points {
    /// Coordinates per point (0 for an empty list).
    pub dim: usize,
    /// The coordinates, point after point.
    pub flat: Vec<f64>,
}

impl Points {
    /// Points from rows of one length (for points the library hands out).
    ///
    /// # Panics
    /// On rows of different lengths.
    pub fn from_rows(rows: &[Vec<f64>]) -> Points {
        let dim = rows.first().map_or(0, Vec::len);
        assert!(rows.iter().all(|r| r.len() == dim), "ragged rows");
        Points {
            dim,
            flat: rows.concat(),
        }
    }

    /// Number of points.
    pub fn len(&self) -> usize {
        self.flat.len().checked_div(self.dim).unwrap_or(0)
    }

    /// No points.
    pub fn is_empty(&self) -> bool {
        self.flat.is_empty()
    }

    /// The points as vectors.
    pub fn to_rows(&self) -> Vec<Vec<f64>> {
        self.rows().map(<[f64]>::to_vec).collect()
    }

    /// The points as slices.
    pub fn rows(&self) -> impl Iterator<Item = &[f64]> {
        self.flat.chunks_exact(self.dim.max(1))
    }
}

/// A control net: `rows` rows of `cols` points of dimension `dim`, row-major.
///
/// In a file: `[[[x, y, z], ...], ...]`, `net[i][j]` the point of row i, column j.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Net {
    /// Number of rows.
    pub rows: usize,
    /// Points per row.
    pub cols: usize,
    /// Coordinates per point.
    pub dim: usize,
    /// The coordinates, row after row.
    pub flat: Vec<f64>,
}

/// One point appended to `out`; `want` is the dimension of the first point, if read.
struct Coords<'a> {
    out: &'a mut Vec<f64>,
    want: Option<usize>,
}

impl<'de> DeserializeSeed<'de> for Coords<'_> {
    type Value = usize;
    fn deserialize<D: Deserializer<'de>>(self, d: D) -> Result<usize, D::Error> {
        d.deserialize_seq(self)
    }
}

impl<'de> Visitor<'de> for Coords<'_> {
    type Value = usize;
    fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str("an array of coordinates like [x, y]")
    }
    fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<usize, A::Error> {
        let start = self.out.len();
        while let Some(x) = seq.next_element::<Finite>()? {
            self.out.push(x.0);
        }
        let n = self.out.len() - start;
        if n == 0 {
            return Err(de::Error::custom("has no coordinates"));
        }
        match self.want {
            Some(d) if d != n => Err(de::Error::custom(format!(
                "has {} but the first point has {d}",
                count(n, "coordinate")
            ))),
            _ => Ok(n),
        }
    }
}

/// A row of points appended to `out`: (points, dimension).
struct Row<'a> {
    out: &'a mut Vec<f64>,
    want_dim: Option<usize>,
    want_len: Option<usize>,
    /// Index of the row in its net.
    index: usize,
}

impl<'de> DeserializeSeed<'de> for Row<'_> {
    type Value = (usize, Option<usize>);
    fn deserialize<D: Deserializer<'de>>(self, d: D) -> Result<Self::Value, D::Error> {
        d.deserialize_seq(self)
    }
}

impl<'de> Visitor<'de> for Row<'_> {
    type Value = (usize, Option<usize>);
    fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str("an array of points like [[x, y], ...]")
    }
    fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<Self::Value, A::Error> {
        let mut dim = self.want_dim;
        let mut n = 0;
        while let Some(d) = seq.next_element_seed(Coords {
            out: self.out,
            want: dim,
        })? {
            dim = Some(d);
            n += 1;
        }
        match self.want_len {
            Some(m) if m != n => Err(de::Error::custom(format!(
                "ragged net: row {} has {} but row 0 has {m} (every row of a net needs the same \
                 number of points)",
                self.index,
                count(n, "point")
            ))),
            _ => Ok((n, dim)),
        }
    }
}

impl<'de> Deserialize<'de> for Points {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Points, D::Error> {
        let mut flat = Vec::new();
        let (_, dim) = d.deserialize_seq(Row {
            out: &mut flat,
            want_dim: None,
            want_len: None,
            index: 0,
        })?;
        Ok(Points {
            dim: dim.unwrap_or(0),
            flat,
        })
    }
}

struct NetVisitor;

impl<'de> Visitor<'de> for NetVisitor {
    type Value = Net;
    fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str("an array of rows of points like [[[x, y, z], ...], ...]")
    }
    fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<Net, A::Error> {
        let mut flat = Vec::new();
        let (mut rows, mut cols, mut dim) = (0, None, None);
        while let Some((n, d)) = seq.next_element_seed(Row {
            out: &mut flat,
            want_dim: dim,
            want_len: cols,
            index: rows,
        })? {
            rows += 1;
            cols = Some(n);
            dim = dim.or(d);
        }
        Ok(Net {
            rows,
            cols: cols.unwrap_or(0),
            dim: dim.unwrap_or(0),
            flat,
        })
    }
}

impl<'de> Deserialize<'de> for Net {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Net, D::Error> {
        d.deserialize_seq(NetVisitor)
    }
}

impl Serialize for Points {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        let mut seq = s.serialize_seq(Some(self.len()))?;
        for p in self.rows() {
            seq.serialize_element(p)?;
        }
        seq.end()
    }
}

impl Serialize for Net {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        let mut seq = s.serialize_seq(Some(self.rows))?;
        for row in self.flat.chunks_exact((self.cols * self.dim).max(1)) {
            let points: Vec<&[f64]> = row.chunks_exact(self.dim.max(1)).collect();
            seq.serialize_element(&points)?;
        }
        seq.end()
    }
}
