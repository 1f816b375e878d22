//! Enums named once (pydantic-core's `serialization_mode!` pattern): one `named_enum!` gives
//! an enum its variants' names, and from them `ALL`, `NAMES`, `name`, `from_name` and `choices`
//! (the names as a message lists them, `a, b or c`). A front end that lists the choices (an
//! error, `--help`, a Python exception) reads them from here, never from a copy.

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
