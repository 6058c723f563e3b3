//! Per-record checksums: a 64-bit FNV-1a hash over the canonical bytes of each stored row, kept in
//! the `checksum` column (schema version 2) and checked whenever a record is read back, exported or
//! merged.
//!
//! Why FNV-1a and not a cryptographic hash: the checksum guards against accidental damage (a bad
//! disk sector, a bit flipped in transit, a file edited by mistake), not against an adversary who
//! could rewrite the checksum too. FNV-1a is a few lines with no dependency, and it detects every
//! change of a single byte with certainty: each step `h = (h ^ byte) * P` is a bijection of the
//! state for a fixed byte (XOR, then multiplication by an odd number modulo 2^64), so two inputs of
//! the same length that differ in one byte always end in different states. Larger damage goes
//! undetected with probability about 2^-64. SQLite's `PRAGMA quick_check` on open covers the pages
//! and B-trees around the records.
//!
//! The canonical bytes are the row's columns in a fixed order, each as a type tag and its value
//! (texts length-prefixed, numbers as IEEE-754 bits), computed from the values *as SQLite stores
//! them* (a NaN becomes NULL, `-0.0` becomes 0), so the writer and every later reader agree.

use crate::row::Column;

/// FNV-1a 64-bit offset basis (<http://www.isthe.com/chongo/tech/comp/fnv/>).
const FNV_OFFSET_BASIS: u64 = 0xcbf2_9ce4_8422_2325;

/// FNV-1a 64-bit prime.
const FNV_PRIME: u64 = 0x0000_0100_0000_01b3;

/// FNV-1a 64 of `bytes`, continuing from `state`.
fn fnv1a(mut state: u64, bytes: &[u8]) -> u64 {
    for &byte in bytes {
        state ^= u64::from(byte);
        state = state.wrapping_mul(FNV_PRIME);
    }
    state
}

/// The checksum of a record's columns (in [`crate::row::RECORD_COLUMNS_SQL`] order, without the
/// checksum itself), as the signed 64-bit integer SQLite stores.
pub(crate) fn record_checksum(columns: &[Column<'_>]) -> i64 {
    let mut state = FNV_OFFSET_BASIS;
    for column in columns {
        state = match *column {
            Column::Null => fnv1a(state, &[0]),
            Column::Number(value) => {
                // As SQLite stores it: NaN is NULL, -0.0 is 0.
                if value.is_nan() {
                    fnv1a(state, &[0])
                } else {
                    let value = if value.to_bits() == (-0.0_f64).to_bits() { 0.0 } else { value };
                    fnv1a(fnv1a(state, &[1]), &value.to_bits().to_le_bytes())
                }
            }
            Column::Text(bytes) => {
                let length = (bytes.len() as u64).to_le_bytes();
                fnv1a(fnv1a(fnv1a(state, &[2]), &length), bytes)
            }
            Column::Blob(bytes) => {
                let length = (bytes.len() as u64).to_le_bytes();
                fnv1a(fnv1a(fnv1a(state, &[3]), &length), bytes)
            }
        };
    }
    // The bits as SQLite's signed INTEGER.
    i64::from_le_bytes(state.to_le_bytes())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fnv1a_matches_the_published_test_vectors() {
        assert_eq!(fnv1a(FNV_OFFSET_BASIS, b""), 0xcbf2_9ce4_8422_2325);
        assert_eq!(fnv1a(FNV_OFFSET_BASIS, b"a"), 0xaf63_dc4c_8601_ec8c);
        assert_eq!(fnv1a(FNV_OFFSET_BASIS, b"foobar"), 0x8594_4171_f739_67e8);
    }

    #[test]
    fn every_single_byte_change_changes_the_checksum() {
        let text = b"[[\"gap_m\",0.00075],[\"turns\",120]]".to_vec();
        let reference = record_checksum(&[Column::Text(&text), Column::Number(0.31)]);
        for position in 0..text.len() {
            for bit in 0..8 {
                let mut flipped = text.clone();
                flipped[position] ^= 1 << bit;
                let changed = record_checksum(&[Column::Text(&flipped), Column::Number(0.31)]);
                assert_ne!(changed, reference, "flip of bit {bit} of byte {position}");
            }
        }
    }

    #[test]
    fn columns_are_delimited_and_stored_forms_agree() {
        let split = |a: &[u8], b: &[u8]| record_checksum(&[Column::Text(a), Column::Text(b)]);
        assert_ne!(split(b"ab", b"c"), split(b"a", b"bc"));
        assert_ne!(record_checksum(&[Column::Null]), record_checksum(&[Column::Text(b"")]));
        assert_eq!(
            record_checksum(&[Column::Number(-0.0)]),
            record_checksum(&[Column::Number(0.0)])
        );
        assert_eq!(record_checksum(&[Column::Number(f64::NAN)]), record_checksum(&[Column::Null]));
    }
}
