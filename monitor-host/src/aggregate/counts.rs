//! Counts keyed by name (per ability, per infraction list), in a fixed order.

use serde::Serialize;

/// Counts keyed by name, serialised as a JSON object in this order.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Counts<T>(pub Vec<(String, T)>);

impl<T: Copy + Default> Counts<T> {
    /// The count of `name` (default when absent).
    pub fn get(&self, name: &str) -> T {
        self.0
            .iter()
            .find(|(n, _)| n == name)
            .map_or_else(T::default, |(_, c)| *c)
    }

    /// The count of `name`, added (as the default) when absent.
    pub fn entry(&mut self, name: &str) -> &mut T {
        let i = match self.0.iter().position(|(n, _)| n == name) {
            Some(i) => i,
            None => {
                self.0.push((name.to_string(), T::default()));
                self.0.len() - 1
            }
        };
        &mut self.0[i].1
    }
}

impl<T: Serialize> Serialize for Counts<T> {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.collect_map(self.0.iter().map(|(k, v)| (k, v)))
    }
}

impl<'de, T: serde::Deserialize<'de>> serde::Deserialize<'de> for Counts<T> {
    /// In the file's key order (the order is the report's).
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        crate::named::pairs(d).map(Counts)
    }
}
