//! CSV from serde: the header of a record type is its serialized field
//! names, each row the same serialization of one record, so that the CSV
//! says what the JSON of the record says.
//!
//! A record is a struct of scalar fields (a flattened struct counts as its
//! fields). Floats are written in scientific notation with the record
//! type's digits ([`CsvRecord::DIGITS`]), `None` as an empty cell, a unit
//! variant as its serialized name, and a unit struct as its name: how a
//! record writes a word such as `n/a` where its JSON has `null`.

use serde::ser::{self, Impossible, Serialize, SerializeMap, SerializeStruct, Serializer};
use std::borrow::Cow;
use std::fmt;

/// A record written as rows of a CSV file.
///
/// `Default` gives the record the header is named from (a file gets its
/// header before its first row, also when it gets none).
pub trait CsvRecord: Serialize + Default {
    /// Digits after the decimal point of every float (`{:.DIGITS$e}`).
    const DIGITS: usize;
    /// Fields of the record's JSON that are not columns of its CSV (lists,
    /// reasons in words that only some records give).
    const JSON_ONLY: &'static [&'static str] = &[];
}

/// The header line of `T` (without the newline): its field names.
pub fn header<T: CsvRecord>() -> std::io::Result<String> {
    header_of(&T::default())
}

/// The header line of the rows like `record` (without the newline): its
/// field names, for a record whose names depend on its values (a column
/// named after a parameter).
pub fn header_of<T: CsvRecord>(record: &T) -> std::io::Result<String> {
    let names: Vec<Cow<'static, str>> = cells(record)?.into_iter().map(|(name, _)| name).collect();
    Ok(names.join(","))
}

/// `record` as a line of its CSV (without the newline), in the order of
/// [`header`].
pub fn row<T: CsvRecord>(record: &T) -> std::io::Result<String> {
    let values: Vec<String> = cells(record)?.into_iter().map(|(_, value)| value).collect();
    Ok(values.join(","))
}

/// The fields of `record` with their cells.
fn cells<T: CsvRecord>(record: &T) -> std::io::Result<Vec<(Cow<'static, str>, String)>> {
    match record.serialize(Csv {
        digits: T::DIGITS,
        json_only: T::JSON_ONLY,
    }) {
        Ok(Out::Row(cells)) => Ok(cells),
        Ok(Out::Cell(_)) => Err(NotFlat("a CSV record is a struct, not a value".into()).into()),
        Err(e) => Err(e.into()),
    }
}

/// Why a value cannot be written as CSV: it is not a struct of scalars.
#[derive(Debug)]
pub struct NotFlat(String);

impl fmt::Display for NotFlat {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "not a flat CSV record: {}", self.0)
    }
}

impl std::error::Error for NotFlat {}

impl ser::Error for NotFlat {
    fn custom<T: fmt::Display>(msg: T) -> Self {
        NotFlat(msg.to_string())
    }
}

impl From<NotFlat> for std::io::Error {
    fn from(e: NotFlat) -> Self {
        std::io::Error::other(e)
    }
}

/// What a value serializes to: one cell, or a row of named cells.
enum Out {
    Cell(String),
    Row(Vec<(Cow<'static, str>, String)>),
}

/// The serializer: a struct or map gives a row, a scalar a cell.
#[derive(Clone, Copy)]
struct Csv {
    digits: usize,
    /// Fields left out ([`CsvRecord::JSON_ONLY`]).
    json_only: &'static [&'static str],
}

impl Csv {
    /// `value` as one cell (a struct inside a field is refused).
    fn cell<T: Serialize + ?Sized>(self, value: &T) -> Result<String, NotFlat> {
        match value.serialize(self)? {
            Out::Cell(c) => Ok(c),
            Out::Row(_) => Err(NotFlat("a struct inside a field".into())),
        }
    }
}

/// A text cell, quoted (RFC 4180) when it holds a comma, a quote or a line break.
fn quoted(text: &str) -> String {
    if text.contains([',', '"', '\n', '\r']) {
        format!("\"{}\"", text.replace('"', "\"\""))
    } else {
        text.to_string()
    }
}

/// Serializer methods for values a cell cannot hold.
macro_rules! refuse {
    ($($method:ident($($arg:ident: $ty:ty),*) -> $out:ty;)*) => {
        $(fn $method(self, $($arg: $ty),*) -> Result<$out, NotFlat> {
            $(let _ = $arg;)*
            Err(NotFlat(concat!("no CSV cell for ", stringify!($method)).into()))
        })*
    };
}

/// Serializer methods for integers: their decimal digits.
macro_rules! integers {
    ($($method:ident: $ty:ty),*) => {
        $(fn $method(self, v: $ty) -> Result<Out, NotFlat> {
            Ok(Out::Cell(v.to_string()))
        })*
    };
}

impl Serializer for Csv {
    type Ok = Out;
    type Error = NotFlat;
    type SerializeSeq = Impossible<Out, NotFlat>;
    type SerializeTuple = Impossible<Out, NotFlat>;
    type SerializeTupleStruct = Impossible<Out, NotFlat>;
    type SerializeTupleVariant = Impossible<Out, NotFlat>;
    type SerializeMap = Row;
    type SerializeStruct = Row;
    type SerializeStructVariant = Impossible<Out, NotFlat>;

    integers!(serialize_i8: i8, serialize_i16: i16, serialize_i32: i32, serialize_i64: i64,
              serialize_u8: u8, serialize_u16: u16, serialize_u32: u32, serialize_u64: u64);

    fn serialize_bool(self, v: bool) -> Result<Out, NotFlat> {
        Ok(Out::Cell(v.to_string()))
    }

    fn serialize_f32(self, v: f32) -> Result<Out, NotFlat> {
        self.serialize_f64(f64::from(v))
    }

    fn serialize_f64(self, v: f64) -> Result<Out, NotFlat> {
        Ok(Out::Cell(format!("{v:.*e}", self.digits)))
    }

    fn serialize_char(self, v: char) -> Result<Out, NotFlat> {
        Ok(Out::Cell(quoted(&v.to_string())))
    }

    fn serialize_str(self, v: &str) -> Result<Out, NotFlat> {
        Ok(Out::Cell(quoted(v)))
    }

    fn serialize_none(self) -> Result<Out, NotFlat> {
        Ok(Out::Cell(String::new()))
    }

    fn serialize_some<T: Serialize + ?Sized>(self, value: &T) -> Result<Out, NotFlat> {
        value.serialize(self)
    }

    fn serialize_unit(self) -> Result<Out, NotFlat> {
        Ok(Out::Cell(String::new()))
    }

    fn serialize_unit_struct(self, name: &'static str) -> Result<Out, NotFlat> {
        Ok(Out::Cell(quoted(name)))
    }

    fn serialize_unit_variant(
        self,
        _name: &'static str,
        _index: u32,
        variant: &'static str,
    ) -> Result<Out, NotFlat> {
        Ok(Out::Cell(quoted(variant)))
    }

    fn serialize_newtype_struct<T: Serialize + ?Sized>(
        self,
        _name: &'static str,
        value: &T,
    ) -> Result<Out, NotFlat> {
        value.serialize(self)
    }

    fn serialize_newtype_variant<T: Serialize + ?Sized>(
        self,
        _name: &'static str,
        _index: u32,
        variant: &'static str,
        _value: &T,
    ) -> Result<Out, NotFlat> {
        Err(NotFlat(format!(
            "no CSV cell for the variant {variant} with a value"
        )))
    }

    refuse! {
        serialize_bytes(v: &[u8]) -> Out;
        serialize_seq(len: Option<usize>) -> Self::SerializeSeq;
        serialize_tuple(len: usize) -> Self::SerializeTuple;
        serialize_tuple_struct(name: &'static str, len: usize) -> Self::SerializeTupleStruct;
        serialize_tuple_variant(name: &'static str, index: u32, variant: &'static str, len: usize)
            -> Self::SerializeTupleVariant;
        serialize_struct_variant(name: &'static str, index: u32, variant: &'static str, len: usize)
            -> Self::SerializeStructVariant;
    }

    fn serialize_map(self, _len: Option<usize>) -> Result<Row, NotFlat> {
        Ok(Row::new(self))
    }

    fn serialize_struct(self, _name: &'static str, len: usize) -> Result<Row, NotFlat> {
        let mut row = Row::new(self);
        row.cells.reserve(len);
        Ok(row)
    }
}

/// The named cells of a record, as its fields are serialized (a map: the
/// fields of a flattened struct among them).
struct Row {
    csv: Csv,
    key: Option<String>,
    cells: Vec<(Cow<'static, str>, String)>,
}

impl Row {
    fn new(csv: Csv) -> Row {
        Row {
            csv,
            key: None,
            cells: Vec::new(),
        }
    }
}

impl SerializeStruct for Row {
    type Ok = Out;
    type Error = NotFlat;

    fn serialize_field<T: Serialize + ?Sized>(
        &mut self,
        key: &'static str,
        value: &T,
    ) -> Result<(), NotFlat> {
        if !self.csv.json_only.contains(&key) {
            let cell = self.csv.cell(value)?;
            self.cells.push((Cow::Borrowed(key), cell));
        }
        Ok(())
    }

    /// Every row has every column: a field skipped in some records is refused.
    fn skip_field(&mut self, key: &'static str) -> Result<(), NotFlat> {
        Err(NotFlat(format!("the field {key} is skipped")))
    }

    fn end(self) -> Result<Out, NotFlat> {
        Ok(Out::Row(self.cells))
    }
}

impl SerializeMap for Row {
    type Ok = Out;
    type Error = NotFlat;

    fn serialize_key<T: Serialize + ?Sized>(&mut self, key: &T) -> Result<(), NotFlat> {
        self.key = Some(self.csv.cell(key)?);
        Ok(())
    }

    fn serialize_value<T: Serialize + ?Sized>(&mut self, value: &T) -> Result<(), NotFlat> {
        let key = self
            .key
            .take()
            .ok_or_else(|| NotFlat("a value without a key".into()))?;
        if !self.csv.json_only.contains(&key.as_str()) {
            let cell = self.csv.cell(value)?;
            self.cells.push((Cow::Owned(key), cell));
        }
        Ok(())
    }

    fn end(self) -> Result<Out, NotFlat> {
        Ok(Out::Row(self.cells))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[derive(Default, serde::Serialize)]
    struct Inner {
        b: Option<f64>,
        #[serde(rename = "C")]
        c: bool,
    }

    #[derive(Default, serde::Serialize)]
    struct Outer {
        a: f64,
        #[serde(flatten)]
        inner: Inner,
        d: &'static str,
    }

    impl CsvRecord for Outer {
        const DIGITS: usize = 3;
    }

    #[derive(Default, serde::Serialize)]
    struct Nested {
        inner: Inner,
    }

    impl CsvRecord for Nested {
        const DIGITS: usize = 3;
    }

    #[test]
    fn a_flattened_record_is_one_row_named_as_serialized() {
        assert_eq!(header::<Outer>().unwrap(), "a,b,C,d");
        let r = Outer {
            a: 1234.0,
            inner: Inner { b: None, c: true },
            d: "x, \"y\"",
        };
        assert_eq!(row(&r).unwrap(), "1.234e3,,true,\"x, \"\"y\"\"\"");
    }

    #[test]
    fn a_nested_struct_is_refused() {
        assert!(header::<Nested>().is_err());
    }
}
