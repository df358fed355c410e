//! A guard against a dictionary page that claims more values than its bytes hold.
//!
//! The `parquet` crate's decoder sizes a dictionary of fixed-width values by the count its
//! page header claims, before reading them: a corrupt or crafted header claiming a billion
//! doubles asks for 8 GB, and a failed allocation aborts the process, which no `catch_unwind`
//! can turn into an error. Before any row is read, the first page of every column chunk that
//! has a dictionary is read on its own, and a PLAIN dictionary whose values would not fit in
//! its (decompressed) bytes is an error at opening.

use std::panic::AssertUnwindSafe;
use std::sync::Arc;

use parquet::basic::{Encoding, Type};
use parquet::column::page::{Page, PageReader};
use parquet::file::metadata::ParquetMetaData;
use parquet::file::reader::ChunkReader;
use parquet::file::serialized_reader::SerializedPageReader;

/// Bytes of one PLAIN value of a fixed-width physical type (`None` for the others).
fn plain_width(physical: Type, type_length: i32) -> Option<usize> {
    match physical {
        Type::INT32 | Type::FLOAT => Some(4),
        Type::INT64 | Type::DOUBLE => Some(8),
        Type::INT96 => Some(12),
        Type::FIXED_LEN_BYTE_ARRAY => usize::try_from(type_length).ok(),
        Type::BOOLEAN | Type::BYTE_ARRAY => None,
    }
}

/// Checks the dictionary page of every column chunk of `metadata` in `reader` (see the
/// module docs). The error gives the page's offset and what it claims. A page that cannot be
/// read here is left to the decoder, which reports it when its rows are read.
pub(crate) fn check_dictionaries<R: ChunkReader + 'static>(
    metadata: &ParquetMetaData,
    reader: &Arc<R>,
) -> Result<(), (u64, String)> {
    for (g, group) in metadata.row_groups().iter().enumerate() {
        let rows = usize::try_from(group.num_rows()).unwrap_or(0);
        for (c, chunk) in group.columns().iter().enumerate() {
            let Some(offset) = chunk.dictionary_page_offset() else {
                continue;
            };
            let descr = chunk.column_descr();
            let Some(width) = plain_width(chunk.column_type(), descr.type_length()) else {
                continue;
            };
            let first = std::panic::catch_unwind(AssertUnwindSafe(|| {
                SerializedPageReader::new(Arc::clone(reader), chunk, rows, None)?.get_next_page()
            }));
            let Ok(Ok(Some(Page::DictionaryPage {
                buf,
                num_values,
                encoding,
                ..
            }))) = first
            else {
                continue;
            };
            let plain = matches!(encoding, Encoding::PLAIN | Encoding::PLAIN_DICTIONARY);
            let needs = usize::try_from(num_values)
                .unwrap_or(usize::MAX)
                .saturating_mul(width);
            if plain && needs > buf.len() {
                return Err((
                    u64::try_from(offset).unwrap_or(0),
                    format!(
                        "row group {g}, column {c} ({}): a dictionary page claiming {num_values} \
                         values of {width} bytes in {} bytes",
                        chunk.column_path(),
                        buf.len()
                    ),
                ));
            }
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::plain_width;
    use parquet::basic::Type;

    #[test]
    fn fixed_widths_are_those_of_the_format() {
        assert_eq!(plain_width(Type::DOUBLE, 0), Some(8));
        assert_eq!(plain_width(Type::FLOAT, 0), Some(4));
        assert_eq!(plain_width(Type::INT96, 0), Some(12));
        assert_eq!(plain_width(Type::FIXED_LEN_BYTE_ARRAY, 16), Some(16));
        assert_eq!(plain_width(Type::FIXED_LEN_BYTE_ARRAY, -1), None);
        assert_eq!(plain_width(Type::BYTE_ARRAY, 0), None);
    }
}
