//! Enums named once (pydantic-core's `serialization_mode!` pattern): one `named_enum!` gives
//! an enum its variants' names, and from them `ALL`, `NAMES`, `name`, `from_name`, `choices`
//! (the names as a message lists them, `a, b or c`) and `Deserialize` (by name). A front end
//! that lists the choices (an error, `--help`, a Python exception) reads them from here, never
//! from a copy.

/// Declares an enum whose every variant has a name (`Variant = "name"`), with:
/// - `ALL`: every variant, in declaration order; `NAMES`: their names, in the same order;
/// - `name(self)` and `from_name(&str)` (exact match);
/// - `choices()`: the names joined as a message lists them (`error, first, last or all`).
macro_rules! named_enum {
    (
        $(#[$meta:meta])*
        $vis:vis enum $Name:ident {
            $( $(#[$vmeta:meta])* $Var:ident = $text:literal ),+ $(,)?
        }
    ) => {
        $(#[$meta])*
        $vis enum $Name {
            $( $(#[$vmeta])* $Var ),+
        }

        impl $Name {
            /// Every value, in declaration order.
            pub const ALL: &'static [$Name] = &[$($Name::$Var),+];
            /// Every value's name, in declaration order.
            pub const NAMES: &'static [&'static str] = &[$($text),+];

            /// The value's name (as settings, reports and every front end spell it).
            pub fn name(self) -> &'static str {
                match self {
                    $($Name::$Var => $text),+
                }
            }

            /// The value of a name (exact, no trimming), or `None`.
            pub fn from_name(name: &str) -> Option<Self> {
                match name {
                    $($text => Some($Name::$Var),)+
                    _ => None,
                }
            }

            /// The names as a message lists them: `a, b or c`.
            pub fn choices() -> String {
                $crate::named::choices(Self::NAMES)
            }
        }

        /// Read back by its name, as reports and settings write it.
        impl<'de> serde::Deserialize<'de> for $Name {
            fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
                let name = <String as serde::Deserialize>::deserialize(d)?;
                Self::from_name(&name).ok_or_else(|| {
                    <D::Error as serde::de::Error>::custom(format!(
                        "unknown name {name:?}; expected {}",
                        Self::choices()
                    ))
                })
            }
        }
    };
}

/// Names joined as a message lists them: `a`, `a or b`, `a, b or c`.
///
/// ```
/// use monitor_host::named::choices;
/// assert_eq!(choices(&["all", "found"]), "all or found");
/// assert_eq!(choices(&["error", "first", "last"]), "error, first or last");
/// ```
pub fn choices(names: &[&str]) -> String {
    match names {
        [] => String::new(),
        [one] => (*one).to_string(),
        [head @ .., last] => format!("{} or {last}", head.join(", ")),
    }
}

// Reading the report back with the types that write it (docs/USAGE.md "Reading a report back"):
// a field the report writes as a name of a fixed vocabulary (an event's kind, an ability) is
// read back as the `&'static str` it was, and an object whose key order is part of the report
// (infraction counts, per-ability counts) in the file's order.

/// A report field holding a name of a fixed vocabulary (`&'static str`: an event's kind, an
/// ability), read back through `name_field!`. Spelled through this alias so that serde's derive
/// does not take the field for text borrowed from its input.
pub type Name = &'static str;

/// `s` as the name of `names` it is, or an error listing them.
pub(crate) fn name_in<E: serde::de::Error>(
    s: &str,
    names: &[&'static str],
) -> Result<&'static str, E> {
    names.iter().find(|n| **n == s).copied().ok_or_else(|| {
        E::custom(format!(
            "unknown name {s:?}; expected {}",
            crate::named::choices(names)
        ))
    })
}

/// A name of `names`, read back as the `&'static str` the report wrote.
pub(crate) fn one_of<'de, D: serde::Deserializer<'de>>(
    d: D,
    names: &[&'static str],
) -> Result<&'static str, D::Error> {
    name_in(&<String as serde::Deserialize>::deserialize(d)?, names)
}

/// A name of `names` or null.
pub(crate) fn opt_one_of<'de, D: serde::Deserializer<'de>>(
    d: D,
    names: &[&'static str],
) -> Result<Option<&'static str>, D::Error> {
    <Option<String> as serde::Deserialize>::deserialize(d)?
        .map(|s| name_in(&s, names))
        .transpose()
}

/// A JSON object read in the file's key order (a `serde_json::Value` would sort its keys).
pub(crate) fn pairs<'de, D, V>(d: D) -> Result<Vec<(String, V)>, D::Error>
where
    D: serde::Deserializer<'de>,
    V: serde::Deserialize<'de>,
{
    struct Pairs<V>(std::marker::PhantomData<V>);
    impl<'de, V: serde::Deserialize<'de>> serde::de::Visitor<'de> for Pairs<V> {
        type Value = Vec<(String, V)>;
        fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
            f.write_str("an object")
        }
        fn visit_map<A: serde::de::MapAccess<'de>>(
            self,
            mut m: A,
        ) -> Result<Self::Value, A::Error> {
            let mut out = Vec::new();
            while let Some(entry) = m.next_entry::<String, V>()? {
                out.push(entry);
            }
            Ok(out)
        }
    }
    d.deserialize_map(Pairs(std::marker::PhantomData))
}

/// Declares `fn $f(d) -> Result<&'static str, _>` (or `Option<&'static str>` with `opt`), for
/// `#[serde(deserialize_with = "...")]` on a field that holds one of `$names`.
macro_rules! name_field {
    ($f:ident, $names:expr) => {
        fn $f<'de, D: serde::Deserializer<'de>>(d: D) -> Result<&'static str, D::Error> {
            $crate::named::one_of(d, &$names)
        }
    };
    (opt $f:ident, $names:expr) => {
        fn $f<'de, D: serde::Deserializer<'de>>(d: D) -> Result<Option<&'static str>, D::Error> {
            $crate::named::opt_one_of(d, &$names)
        }
    };
}
