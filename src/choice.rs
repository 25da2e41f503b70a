//! The shared vocabulary of choices: which arithmetic decides ([`Path`]), and the
//! string names every option enum parses from and prints as ([`UnknownName`]).

/// Implements `FromStr`, `Display` and a `NAMES` constant for a fieldless enum whose
/// variants have fixed kebab-case names.
macro_rules! named_enum {
    ($ty:ident { $($variant:ident => $name:literal),+ $(,)? }) => {
        impl $ty {
            /// Every accepted name, in declaration order.
            pub const NAMES: &'static [&'static str] = &[$($name),+];

            /// The name this value parses from and prints as.
            pub fn name(self) -> &'static str {
                match self {
                    $($ty::$variant => $name),+
                }
            }
        }

        impl ::std::str::FromStr for $ty {
            type Err = $crate::UnknownName;

            fn from_str(s: &str) -> Result<Self, Self::Err> {
                match s {
                    $($name => Ok($ty::$variant),)+
                    _ => Err($crate::UnknownName {
                        what: stringify!($ty),
                        got: s.to_string(),
                        expected: Self::NAMES,
                    }),
                }
            }
        }

        impl ::std::fmt::Display for $ty {
            fn fmt(&self, f: &mut ::std::fmt::Formatter<'_>) -> ::std::fmt::Result {
                f.write_str(self.name())
            }
        }
    };
}
pub(crate) use named_enum;

/// Builder-style setters (`with_x(self, value) -> Self`) and `new()` (the defaults) for an
/// options struct marked `#[non_exhaustive]`, so that fields can be added without breaking
/// callers: `Options::new().with_k(20)`.
macro_rules! setters {
    ($ty:ident { $($with:ident => $field:ident : $fty:ty),+ $(,)? }) => {
        impl $ty {
            /// The defaults (as `Default::default()`).
            pub fn new() -> Self {
                Self::default()
            }
            $(
                #[doc = concat!("Sets [`", stringify!($ty), "::", stringify!($field), "`].")]
                #[must_use]
                pub fn $with(mut self, value: $fty) -> Self {
                    self.$field = value;
                    self
                }
            )+
        }
    };
}
pub(crate) use setters;

/// A name that is not one of an option's values (from any option enum's `FromStr`).
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("{what}: unknown value {got:?} (expected one of: {})", expected.join(", "))]
pub struct UnknownName {
    /// The option type, e.g. `Path`.
    pub what: &'static str,
    /// The string that was given.
    pub got: String,
    /// The accepted names.
    pub expected: &'static [&'static str],
}

/// Which arithmetic decides: the one way every family is told (a `path` field of its
/// options; parsed from `exact`, `fast`, `filtered`).
///
/// * `Exact` — the reference path alone: exact rationals (or integers over a shared
///   denominator where only signs matter). Slow, never wrong.
/// * `Fast` — `f64` with a rigorous rounding-error bound on every decision. Where the bound
///   cannot decide, the positivity and FFD tests answer `Uncertain`; the marching-cubes and
///   decimation engines finish that one predicate exactly instead (their predicates are
///   adaptive), so for them `Fast` and `Filtered` run the same engine.
/// * `Filtered` — `Fast`, and every `Uncertain` part redone on the exact path: as fast as the
///   fast path where it decides, never uncertain.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Default)]
pub enum Path {
    /// Exact rational arithmetic throughout.
    Exact,
    /// Certified `f64`; may report `Uncertain`.
    Fast,
    /// Certified `f64` with an exact fallback (the default).
    #[default]
    Filtered,
}

named_enum!(Path {
    Exact => "exact",
    Fast => "fast",
    Filtered => "filtered",
});

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_round_trip_and_unknown_names_are_refused() {
        for &n in Path::NAMES {
            let p: Path = n.parse().unwrap();
            assert_eq!(p.to_string(), n);
        }
        let e = "quick".parse::<Path>().unwrap_err();
        assert_eq!(e.got, "quick");
        assert!(e.to_string().contains("exact, fast, filtered"), "{e}");
    }
}
