//! Fixed-size arrays (`gravity = [x, y, z]`) read with their length checked. serde's own
//! `[T; N]` stops after N elements, and the toml reader then drops the rest of a plain
//! table's array without a word, so `gravity = [0, -9.81, 0, 5]` used to be read as
//! `[0, -9.81, 0]`. Fields use these through `#[serde(deserialize_with = …)]`.

use serde::de::{Deserialize, Deserializer, Error};

/// A `[T; N]` from an array of exactly N elements.
pub(crate) fn array<'de, D, T, const N: usize>(deserializer: D) -> Result<[T; N], D::Error>
where
    D: Deserializer<'de>,
    T: Deserialize<'de>,
{
    let values = Vec::<T>::deserialize(deserializer)?;
    sized(values)
}

/// An optional `[T; N]`.
pub(crate) fn option_array<'de, D, T, const N: usize>(
    deserializer: D,
) -> Result<Option<[T; N]>, D::Error>
where
    D: Deserializer<'de>,
    T: Deserialize<'de>,
{
    Option::<Vec<T>>::deserialize(deserializer)?
        .map(sized)
        .transpose()
}

/// An optional N × N matrix, given as N rows of N numbers.
pub(crate) fn option_matrix<'de, D, const N: usize>(
    deserializer: D,
) -> Result<Option<[[f64; N]; N]>, D::Error>
where
    D: Deserializer<'de>,
{
    let Some(rows) = Option::<Vec<Vec<f64>>>::deserialize(deserializer)? else {
        return Ok(None);
    };
    let rows = rows
        .into_iter()
        .map(sized)
        .collect::<Result<Vec<[f64; N]>, D::Error>>()?;
    sized(rows).map(Some)
}

fn sized<E: Error, T, const N: usize>(values: Vec<T>) -> Result<[T; N], E> {
    let len = values.len();
    values
        .try_into()
        .map_err(|_| E::invalid_length(len, &format!("an array of {N} elements").as_str()))
}
