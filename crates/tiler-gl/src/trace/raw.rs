//! A trace's JSON split in one pass into the raw text of its parts — the top-level fields,
//! each frame's fields, each call — without building a tree of it: the reader then checks
//! each part and deserialises each call straight into its type. Parts of the wrong kind (a
//! frame that is not an object, `frames` that is not an array) are recorded, not errors here,
//! so the reader can say which frame is at fault.

use serde::de::{Deserialize, Deserializer, IgnoredAny, MapAccess, SeqAccess, Visitor};
use serde_json::value::RawValue;

/// The top level of a trace.
#[derive(Default)]
pub(super) struct Root<'a> {
    pub format: Option<&'a RawValue>,
    pub version: Option<&'a RawValue>,
    pub description: Option<&'a RawValue>,
    pub config: Option<&'a RawValue>,
    /// `None` when missing or not an array.
    pub frames: Option<Vec<Frame<'a>>>,
    /// The first field that is none of the above.
    pub unknown: Option<String>,
    /// The JSON is not an object.
    pub not_object: bool,
}

/// One entry of `frames`.
#[derive(Default)]
pub(super) struct Frame<'a> {
    pub repeat: Option<&'a RawValue>,
    /// `None` when missing or not an array.
    pub calls: Option<Vec<&'a RawValue>>,
    pub unknown: Option<String>,
    /// The entry is not an object.
    pub not_object: bool,
}

/// An array of `T`, or `None` for any other value (skipped without building it).
struct ArrayOr<T>(Option<Vec<T>>);

/// The visit methods of a value that is not what was expected: it is skipped, `$other`.
macro_rules! otherwise {
    ($other:expr) => {
        fn visit_bool<E>(self, _: bool) -> Result<Self::Value, E> {
            Ok($other)
        }
        fn visit_i64<E>(self, _: i64) -> Result<Self::Value, E> {
            Ok($other)
        }
        fn visit_u64<E>(self, _: u64) -> Result<Self::Value, E> {
            Ok($other)
        }
        fn visit_f64<E>(self, _: f64) -> Result<Self::Value, E> {
            Ok($other)
        }
        fn visit_str<E>(self, _: &str) -> Result<Self::Value, E> {
            Ok($other)
        }
        fn visit_unit<E>(self) -> Result<Self::Value, E> {
            Ok($other)
        }
    };
}

impl<'de, T: Deserialize<'de>> Deserialize<'de> for ArrayOr<T> {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        struct V<T>(std::marker::PhantomData<T>);
        impl<'de, T: Deserialize<'de>> Visitor<'de> for V<T> {
            type Value = ArrayOr<T>;
            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                f.write_str("any value")
            }
            fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<ArrayOr<T>, A::Error> {
                // No capacity from a size hint: the input decides it.
                let mut items = Vec::new();
                while let Some(item) = seq.next_element()? {
                    items.push(item);
                }
                Ok(ArrayOr(Some(items)))
            }
            fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<ArrayOr<T>, A::Error> {
                while map.next_entry::<IgnoredAny, IgnoredAny>()?.is_some() {}
                Ok(ArrayOr(None))
            }
            otherwise!(ArrayOr(None));
        }
        deserializer.deserialize_any(V(std::marker::PhantomData))
    }
}

impl<'de: 'a, 'a> Deserialize<'de> for Frame<'a> {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        struct V;
        impl<'de> Visitor<'de> for V {
            type Value = Frame<'de>;
            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                f.write_str("a frame")
            }
            fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<Frame<'de>, A::Error> {
                let mut frame = Frame::default();
                while let Some(key) = map.next_key::<String>()? {
                    match key.as_str() {
                        "repeat" => frame.repeat = Some(map.next_value()?),
                        "calls" => frame.calls = map.next_value::<ArrayOr<&RawValue>>()?.0,
                        _ => {
                            map.next_value::<IgnoredAny>()?;
                            frame.unknown.get_or_insert(key);
                        }
                    }
                }
                Ok(frame)
            }
            fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<Frame<'de>, A::Error> {
                while seq.next_element::<IgnoredAny>()?.is_some() {}
                Ok(Frame { not_object: true, ..Frame::default() })
            }
            otherwise!(Frame { not_object: true, ..Frame::default() });
        }
        deserializer.deserialize_any(V)
    }
}

impl<'de: 'a, 'a> Deserialize<'de> for Root<'a> {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        struct V;
        impl<'de> Visitor<'de> for V {
            type Value = Root<'de>;
            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                f.write_str("a trace")
            }
            fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<Root<'de>, A::Error> {
                let mut root = Root::default();
                while let Some(key) = map.next_key::<String>()? {
                    match key.as_str() {
                        "format" => root.format = Some(map.next_value()?),
                        "version" => root.version = Some(map.next_value()?),
                        "description" => root.description = Some(map.next_value()?),
                        "config" => root.config = Some(map.next_value()?),
                        "frames" => root.frames = map.next_value::<ArrayOr<Frame<'de>>>()?.0,
                        _ => {
                            map.next_value::<IgnoredAny>()?;
                            root.unknown.get_or_insert(key);
                        }
                    }
                }
                Ok(root)
            }
            fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<Root<'de>, A::Error> {
                while seq.next_element::<IgnoredAny>()?.is_some() {}
                Ok(Root { not_object: true, ..Root::default() })
            }
            otherwise!(Root { not_object: true, ..Root::default() });
        }
        deserializer.deserialize_any(V)
    }
}
