//! Numbers in JSON that may be NaN or infinite (a figure with no value, a
//! UGR without a bound): written as "nan", "inf", "-inf" and read back to
//! the same number, so a part file merges to the same CSV as one run.

use serde::{Deserialize, Deserializer, Serialize, Serializer};

#[derive(Serialize, Deserialize)]
#[serde(untagged)]
enum Repr {
    Number(f64),
    Text(String),
}

fn to_repr(v: f64) -> Repr {
    if v.is_finite() {
        Repr::Number(v)
    } else if v.is_nan() {
        Repr::Text("nan".to_owned())
    } else if v > 0.0 {
        Repr::Text("inf".to_owned())
    } else {
        Repr::Text("-inf".to_owned())
    }
}

fn from_repr<E: serde::de::Error>(r: Repr) -> Result<f64, E> {
    match r {
        Repr::Number(v) => Ok(v),
        Repr::Text(t) => match t.as_str() {
            "nan" => Ok(f64::NAN),
            "inf" => Ok(f64::INFINITY),
            "-inf" => Ok(f64::NEG_INFINITY),
            other => Err(E::custom(format!("not a number: {other:?}"))),
        },
    }
}

/// One number.
pub mod one {
    use super::*;

    pub fn serialize<S: Serializer>(v: &f64, s: S) -> Result<S::Ok, S::Error> {
        to_repr(*v).serialize(s)
    }

    pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<f64, D::Error> {
        from_repr(Repr::deserialize(d)?)
    }
}

/// A list of numbers.
pub mod list {
    use super::*;

    pub fn serialize<S: Serializer>(v: &[f64], s: S) -> Result<S::Ok, S::Error> {
        v.iter()
            .map(|x| to_repr(*x))
            .collect::<Vec<_>>()
            .serialize(s)
    }

    pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<Vec<f64>, D::Error> {
        Vec::<Repr>::deserialize(d)?
            .into_iter()
            .map(from_repr)
            .collect()
    }
}

#[cfg(test)]
mod tests {
    #[derive(Debug, PartialEq, serde::Serialize, serde::Deserialize)]
    struct T {
        #[serde(with = "super::list")]
        v: Vec<f64>,
    }

    #[test]
    fn every_number_reads_back_to_the_bit() {
        let t = T {
            v: vec![
                0.1,
                1.0 / 3.0,
                f64::INFINITY,
                f64::NEG_INFINITY,
                -0.0,
                1e-300,
            ],
        };
        let text = serde_json::to_string(&t).expect("writes");
        let back: T = serde_json::from_str(&text).expect("reads");
        for (a, b) in t.v.iter().zip(&back.v) {
            assert_eq!(a.to_bits(), b.to_bits());
        }
        let nan: T = serde_json::from_str(r#"{"v":["nan"]}"#).expect("reads");
        assert!(nan.v[0].is_nan());
    }
}
