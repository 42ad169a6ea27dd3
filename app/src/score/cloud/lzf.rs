//! LZF decompression (Marc Lehmann's format, as PCL's `binary_compressed` PCD uses it): a
//! control byte below 32 starts a run of that many plus one literal bytes; any other is a
//! back-reference of length `(ctrl >> 5) + 2` (7 meaning a further length byte) at distance
//! `((ctrl & 31) << 8) + next byte + 1`. Every read and copy is bounds-checked, and the output
//! never exceeds the size the header gave, so crafted data ends in an error.

/// `input` decompressed into exactly `size` bytes.
pub(super) fn decompress(input: &[u8], size: usize) -> Result<Vec<u8>, String> {
    // Reserve what the input can make at most (a back-reference of 3 bytes makes 264), not
    // what the header says.
    let mut out: Vec<u8> = Vec::with_capacity(size.min(input.len().saturating_mul(88)));
    let mut i = 0;
    let corrupt = |what: &str| Err(format!("binary_compressed data is corrupt ({what})"));
    while i < input.len() {
        let ctrl = usize::from(input[i]);
        i += 1;
        if ctrl < 32 {
            let run = ctrl + 1;
            let Some(literal) = input.get(i..i + run) else {
                return corrupt("a literal run past the end");
            };
            if out.len() + run > size {
                return corrupt("more bytes than its size");
            }
            out.extend_from_slice(literal);
            i += run;
        } else {
            let mut len = (ctrl >> 5) + 2;
            if len == 9 {
                let Some(&more) = input.get(i) else {
                    return corrupt("a length past the end");
                };
                len += usize::from(more);
                i += 1;
            }
            let Some(&low) = input.get(i) else {
                return corrupt("a reference past the end");
            };
            i += 1;
            let back = ((ctrl & 31) << 8) + usize::from(low) + 1;
            if back > out.len() {
                return corrupt("a reference before the start");
            }
            if out.len() + len > size {
                return corrupt("more bytes than its size");
            }
            let from = out.len() - back;
            for k in 0..len {
                out.push(out[from + k]);
            }
        }
    }
    if out.len() != size {
        return Err(format!(
            "binary_compressed data unpacks to {} bytes, not the {size} its header says",
            out.len()
        ));
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn literals_and_overlapping_references_unpack() {
        // "abc" literal, then a reference 3 back of length 6 (overlapping): "abcabcabc".
        let packed = [2, b'a', b'b', b'c', (4 << 5) as u8, 2];
        assert_eq!(decompress(&packed, 9).unwrap(), b"abcabcabc");
        assert!(decompress(&packed, 8).is_err(), "more than its size");
        assert!(decompress(&packed, 10).is_err(), "fewer than its size");
        assert!(
            decompress(&[(1 << 5) as u8, 0], 3).is_err(),
            "before the start"
        );
        assert!(decompress(&[5, b'a'], 6).is_err(), "past the end");
    }
}
