//! A mutation that keeps a glTF's JSON valid: one number, string, array element or key of the
//! document changes, and the bytes are written back (a `.glb`'s JSON chunk and lengths
//! included), so the fuzzer reaches the loader's accessors, views, animations and textures
//! rather than stopping at JSON syntax. The rest of the bundle stays as it is.

use serde_json::{Map, Value};

use crate::SEPARATOR;

/// A small deterministic generator (xorshift), seeded by libFuzzer's seed.
struct Rng(u64);

impl Rng {
    fn below(&mut self, n: usize) -> usize {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        (self.0 % n.max(1) as u64) as usize
    }
}

/// Bundle `data` with its main glTF (JSON or GLB) changed in one place, or `None` where the
/// main file is no glTF whose JSON parses.
pub fn mutate(data: &[u8], seed: u32) -> Option<Vec<u8>> {
    let main_end = data
        .windows(SEPARATOR.len())
        .position(|w| w == SEPARATOR)
        .unwrap_or(data.len());
    let (main, rest) = data.split_at(main_end);
    let mut rng = Rng(u64::from(seed).wrapping_mul(0x9E37_79B9_7F4A_7C15) | 1);
    let glb = Glb::parse(main);
    let json = glb.as_ref().map_or(main, |g| g.json);
    let mut document: Value = serde_json::from_slice(json).ok()?;
    change_one(&mut document, &mut rng);
    let text = serde_json::to_vec(&document).ok()?;
    let mut out = match glb {
        Some(glb) => glb.with_json(&text),
        None => text,
    };
    out.extend_from_slice(rest);
    Some(out)
}

/// A GLB's JSON chunk and what follows it (the binary chunk, as it is).
struct Glb<'a> {
    json: &'a [u8],
    after: &'a [u8],
}

impl<'a> Glb<'a> {
    fn parse(bytes: &'a [u8]) -> Option<Self> {
        if !bytes.starts_with(b"glTF") || bytes.len() < 20 {
            return None;
        }
        let length = u32::from_le_bytes(bytes[12..16].try_into().ok()?) as usize;
        let json = bytes.get(20..20usize.checked_add(length)?)?;
        Some(Glb {
            json,
            after: &bytes[20 + length..],
        })
    }

    fn with_json(&self, json: &[u8]) -> Vec<u8> {
        let mut chunk = json.to_vec();
        while !chunk.len().is_multiple_of(4) {
            chunk.push(b' ');
        }
        let total = 12 + 8 + chunk.len() + self.after.len();
        let mut out = Vec::with_capacity(total);
        out.extend_from_slice(b"glTF");
        out.extend_from_slice(&2u32.to_le_bytes());
        out.extend_from_slice(&(total as u32).to_le_bytes());
        out.extend_from_slice(&(chunk.len() as u32).to_le_bytes());
        out.extend_from_slice(b"JSON");
        out.extend_from_slice(&chunk);
        out.extend_from_slice(self.after);
        out
    }
}

/// Every value of `value`, in document order, counted.
fn count(value: &Value) -> usize {
    1 + match value {
        Value::Array(items) => items.iter().map(count).sum(),
        Value::Object(map) => map.values().map(count).sum(),
        _ => 0,
    }
}

/// Changes the `n`-th value of `value` in document order; whether it was there.
fn change_nth(value: &mut Value, n: &mut usize, rng: &mut Rng) -> bool {
    if *n == 0 {
        *value = changed(value, rng);
        return true;
    }
    *n -= 1;
    match value {
        Value::Array(items) => items.iter_mut().any(|v| change_nth(v, n, rng)),
        Value::Object(map) => map.values_mut().any(|v| change_nth(v, n, rng)),
        _ => false,
    }
}

fn change_one(document: &mut Value, rng: &mut Rng) {
    let mut n = rng.below(count(document));
    change_nth(document, &mut n, rng);
}

/// Numbers a loader is likely to mishandle: bounds, powers of two and their neighbours.
const EDGES: [i64; 12] = [
    0,
    1,
    -1,
    2,
    3,
    4,
    255,
    65_535,
    i32::MAX as i64,
    u32::MAX as i64,
    1 << 40,
    i64::MIN,
];

/// `value` changed in one way the generator picks.
fn changed(value: &Value, rng: &mut Rng) -> Value {
    match value {
        Value::Number(number) => {
            let x = number.as_f64().unwrap_or(0.0);
            match rng.below(4) {
                0 => EDGES[rng.below(EDGES.len())].into(),
                1 => (x as i64).wrapping_add(rng.below(9) as i64 - 4).into(),
                2 => serde_json::Number::from_f64(x * [0.0, -1.0, 1e30, 1e-30][rng.below(4)])
                    .map_or(Value::Null, Value::Number),
                _ => (rng.below(64) as i64).into(),
            }
        }
        Value::Array(items) => {
            let mut items = items.clone();
            match rng.below(3) {
                0 if !items.is_empty() => {
                    items.remove(rng.below(items.len()));
                }
                1 if !items.is_empty() => {
                    let copy = items[rng.below(items.len())].clone();
                    items.push(copy);
                }
                _ => items.push(EDGES[rng.below(EDGES.len())].into()),
            }
            Value::Array(items)
        }
        Value::Object(map) => {
            let mut map: Map<String, Value> = map.clone();
            let keys: Vec<String> = map.keys().cloned().collect();
            if !keys.is_empty() {
                map.remove(&keys[rng.below(keys.len())]);
            }
            Value::Object(map)
        }
        Value::String(s) => Value::String(match rng.below(3) {
            0 => String::new(),
            1 => format!("{s}{s}"),
            _ => s.chars().rev().collect(),
        }),
        Value::Bool(b) => Value::Bool(!b),
        Value::Null => Value::Bool(true),
    }
}
