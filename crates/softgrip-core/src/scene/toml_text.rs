//! A small serde serializer for scene text, in the form `softgrip scene` prints: keys in the
//! order given, `None` left out, numbers as Rust's `{:?}` prints them (the shortest text that
//! reads back to the same value: `1e-5`, `0.001`; `toml::to_string` would write `0.00001`), a
//! blank line after each table, nested arrays of tables (`[[finger.part]]`) after their
//! parent's keys. It knows nothing of scenes.

use std::fmt::Write;

use serde::Serialize;
use serde::ser::{self, Impossible};

/// A serialized value; a table keeps its keys' order.
#[derive(Debug, Clone, PartialEq)]
pub(super) enum Value {
    Integer(i64),
    Float(f64),
    Bool(bool),
    Text(String),
    Array(Vec<Value>),
    Table(Table),
}

pub(super) type Table = Vec<(&'static str, Value)>;

/// `value`, a struct, as a table.
///
/// # Panics
/// When `value` holds what a scene file cannot (a map, an enum, bytes) or is no struct: the
/// raw layer holds only numbers, strings, booleans, arrays and tables.
pub(super) fn to_table<T: Serialize>(value: &T) -> Table {
    match value.serialize(ValueSerializer) {
        Ok(Some(Value::Table(table))) => table,
        Ok(_) => panic!("scene text: a struct must serialize to a table"),
        Err(Unsupported(what)) => panic!("scene text: {what} has no place in a scene file"),
    }
}

/// The text of a document: each of `root`'s tables and arrays of tables, in order.
pub(super) fn document(root: &Table) -> String {
    let mut out = String::new();
    write_nested(&mut out, "", root);
    out
}

/// The `key = value` lines of `table`'s keys that are not tables.
pub(super) fn key_lines(table: &Table) -> String {
    let mut out = String::new();
    for (key, value) in table {
        if !is_nested(value) {
            let _ = writeln!(out, "{key} = {}", inline(value));
        }
    }
    out
}

/// A table or an array of tables: written under its own header. An empty array counts (it
/// writes nothing).
fn is_nested(value: &Value) -> bool {
    match value {
        Value::Table(_) => true,
        Value::Array(items) => items.iter().all(|item| matches!(item, Value::Table(_))),
        _ => false,
    }
}

/// The nested tables of the table at `path`.
fn write_nested(out: &mut String, path: &str, table: &Table) {
    for (key, value) in table {
        let path = if path.is_empty() {
            key.to_string()
        } else {
            format!("{path}.{key}")
        };
        match value {
            Value::Table(inner) => write_table(out, &format!("[{path}]"), &path, inner),
            Value::Array(items) if is_nested(value) => {
                for item in items {
                    if let Value::Table(inner) = item {
                        write_table(out, &format!("[[{path}]]"), &path, inner);
                    }
                }
            }
            _ => {}
        }
    }
}

fn write_table(out: &mut String, header: &str, path: &str, table: &Table) {
    out.push_str(header);
    out.push('\n');
    out.push_str(&key_lines(table));
    out.push('\n');
    write_nested(out, path, table);
}

fn inline(value: &Value) -> String {
    let join = |items: Vec<String>| items.join(", ");
    match value {
        Value::Integer(i) => i.to_string(),
        Value::Float(x) => format!("{x:?}"),
        Value::Bool(b) => b.to_string(),
        Value::Text(s) => format!("{s:?}"),
        Value::Array(items) => format!("[{}]", join(items.iter().map(inline).collect())),
        Value::Table(table) => {
            let pairs = table.iter().map(|(k, v)| format!("{k} = {}", inline(v)));
            format!("{{ {} }}", join(pairs.collect()))
        }
    }
}

/// What a scene file cannot hold.
#[derive(Debug)]
struct Unsupported(String);

impl std::fmt::Display for Unsupported {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for Unsupported {}

impl ser::Error for Unsupported {
    fn custom<T: std::fmt::Display>(msg: T) -> Self {
        Unsupported(msg.to_string())
    }
}

fn unsupported<T>(what: &str) -> Result<T, Unsupported> {
    Err(Unsupported(what.to_string()))
}

/// Serializes into a [`Value`]; `None` (the `Option`) is a key left out.
struct ValueSerializer;

impl ser::Serializer for ValueSerializer {
    type Ok = Option<Value>;
    type Error = Unsupported;
    type SerializeSeq = ArrayBuilder;
    type SerializeTuple = ArrayBuilder;
    type SerializeTupleStruct = Impossible<Option<Value>, Unsupported>;
    type SerializeTupleVariant = Impossible<Option<Value>, Unsupported>;
    type SerializeMap = Impossible<Option<Value>, Unsupported>;
    type SerializeStruct = TableBuilder;
    type SerializeStructVariant = Impossible<Option<Value>, Unsupported>;

    fn serialize_bool(self, v: bool) -> Result<Option<Value>, Unsupported> {
        Ok(Some(Value::Bool(v)))
    }
    fn serialize_i8(self, v: i8) -> Result<Option<Value>, Unsupported> {
        self.serialize_i64(v.into())
    }
    fn serialize_i16(self, v: i16) -> Result<Option<Value>, Unsupported> {
        self.serialize_i64(v.into())
    }
    fn serialize_i32(self, v: i32) -> Result<Option<Value>, Unsupported> {
        self.serialize_i64(v.into())
    }
    fn serialize_i64(self, v: i64) -> Result<Option<Value>, Unsupported> {
        Ok(Some(Value::Integer(v)))
    }
    fn serialize_u8(self, v: u8) -> Result<Option<Value>, Unsupported> {
        self.serialize_i64(v.into())
    }
    fn serialize_u16(self, v: u16) -> Result<Option<Value>, Unsupported> {
        self.serialize_i64(v.into())
    }
    fn serialize_u32(self, v: u32) -> Result<Option<Value>, Unsupported> {
        self.serialize_i64(v.into())
    }
    fn serialize_u64(self, v: u64) -> Result<Option<Value>, Unsupported> {
        match i64::try_from(v) {
            Ok(v) => self.serialize_i64(v),
            Err(_) => unsupported("an integer above 2^63 - 1"),
        }
    }
    fn serialize_f32(self, v: f32) -> Result<Option<Value>, Unsupported> {
        self.serialize_f64(v.into())
    }
    fn serialize_f64(self, v: f64) -> Result<Option<Value>, Unsupported> {
        Ok(Some(Value::Float(v)))
    }
    fn serialize_char(self, v: char) -> Result<Option<Value>, Unsupported> {
        Ok(Some(Value::Text(v.to_string())))
    }
    fn serialize_str(self, v: &str) -> Result<Option<Value>, Unsupported> {
        Ok(Some(Value::Text(v.to_string())))
    }
    fn serialize_bytes(self, _: &[u8]) -> Result<Option<Value>, Unsupported> {
        unsupported("bytes")
    }
    fn serialize_none(self) -> Result<Option<Value>, Unsupported> {
        Ok(None)
    }
    fn serialize_some<T: ?Sized + Serialize>(
        self,
        value: &T,
    ) -> Result<Option<Value>, Unsupported> {
        value.serialize(self)
    }
    fn serialize_unit(self) -> Result<Option<Value>, Unsupported> {
        unsupported("()")
    }
    fn serialize_unit_struct(self, name: &'static str) -> Result<Option<Value>, Unsupported> {
        unsupported(name)
    }
    fn serialize_unit_variant(
        self,
        name: &'static str,
        _: u32,
        _: &'static str,
    ) -> Result<Option<Value>, Unsupported> {
        unsupported(name)
    }
    fn serialize_newtype_struct<T: ?Sized + Serialize>(
        self,
        _: &'static str,
        value: &T,
    ) -> Result<Option<Value>, Unsupported> {
        value.serialize(self)
    }
    fn serialize_newtype_variant<T: ?Sized + Serialize>(
        self,
        name: &'static str,
        _: u32,
        _: &'static str,
        _: &T,
    ) -> Result<Option<Value>, Unsupported> {
        unsupported(name)
    }
    fn serialize_seq(self, len: Option<usize>) -> Result<ArrayBuilder, Unsupported> {
        Ok(ArrayBuilder(Vec::with_capacity(len.unwrap_or(0))))
    }
    fn serialize_tuple(self, len: usize) -> Result<ArrayBuilder, Unsupported> {
        Ok(ArrayBuilder(Vec::with_capacity(len)))
    }
    fn serialize_tuple_struct(
        self,
        name: &'static str,
        _: usize,
    ) -> Result<Self::SerializeTupleStruct, Unsupported> {
        unsupported(name)
    }
    fn serialize_tuple_variant(
        self,
        name: &'static str,
        _: u32,
        _: &'static str,
        _: usize,
    ) -> Result<Self::SerializeTupleVariant, Unsupported> {
        unsupported(name)
    }
    fn serialize_map(self, _: Option<usize>) -> Result<Self::SerializeMap, Unsupported> {
        unsupported("a map")
    }
    fn serialize_struct(self, _: &'static str, len: usize) -> Result<TableBuilder, Unsupported> {
        Ok(TableBuilder(Vec::with_capacity(len)))
    }
    fn serialize_struct_variant(
        self,
        name: &'static str,
        _: u32,
        _: &'static str,
        _: usize,
    ) -> Result<Self::SerializeStructVariant, Unsupported> {
        unsupported(name)
    }
}

struct ArrayBuilder(Vec<Value>);

impl ser::SerializeSeq for ArrayBuilder {
    type Ok = Option<Value>;
    type Error = Unsupported;

    fn serialize_element<T: ?Sized + Serialize>(&mut self, value: &T) -> Result<(), Unsupported> {
        match value.serialize(ValueSerializer)? {
            Some(value) => self.0.push(value),
            None => return unsupported("`None` in an array"),
        }
        Ok(())
    }

    fn end(self) -> Result<Option<Value>, Unsupported> {
        Ok(Some(Value::Array(self.0)))
    }
}

impl ser::SerializeTuple for ArrayBuilder {
    type Ok = Option<Value>;
    type Error = Unsupported;

    fn serialize_element<T: ?Sized + Serialize>(&mut self, value: &T) -> Result<(), Unsupported> {
        ser::SerializeSeq::serialize_element(self, value)
    }

    fn end(self) -> Result<Option<Value>, Unsupported> {
        ser::SerializeSeq::end(self)
    }
}

struct TableBuilder(Table);

impl ser::SerializeStruct for TableBuilder {
    type Ok = Option<Value>;
    type Error = Unsupported;

    fn serialize_field<T: ?Sized + Serialize>(
        &mut self,
        key: &'static str,
        value: &T,
    ) -> Result<(), Unsupported> {
        if let Some(value) = value.serialize(ValueSerializer)? {
            self.0.push((key, value));
        }
        Ok(())
    }

    fn end(self) -> Result<Option<Value>, Unsupported> {
        Ok(Some(Value::Table(self.0)))
    }
}

#[cfg(test)]
mod tests {
    use serde::Serialize;

    use super::*;

    #[derive(Serialize)]
    struct Part {
        offset: [f64; 3],
    }

    #[derive(Serialize)]
    struct Item {
        name: Option<String>,
        absent: Option<f64>,
        count: i64,
        on: bool,
        part: Vec<Part>,
    }

    #[derive(Serialize)]
    struct Doc {
        head: Item,
        item: Vec<Item>,
        none: Vec<Item>,
    }

    #[test]
    fn tables_then_their_arrays_of_tables_each_followed_by_a_blank_line() {
        let item = |name: &str, parts: Vec<Part>| Item {
            name: Some(name.to_string()),
            absent: None,
            count: 3,
            on: true,
            part: parts,
        };
        let doc = Doc {
            head: item("a \"b\"", vec![]),
            item: vec![item(
                "c",
                vec![Part {
                    offset: [1e-5, 0.001, -2.0],
                }],
            )],
            none: vec![],
        };
        assert_eq!(
            document(&to_table(&doc)),
            "[head]\nname = \"a \\\"b\\\"\"\ncount = 3\non = true\n\n\
             [[item]]\nname = \"c\"\ncount = 3\non = true\n\n\
             [[item.part]]\noffset = [1e-5, 0.001, -2.0]\n\n"
        );
    }
}
