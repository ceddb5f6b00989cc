//! Aperture images (`--aperture-image`): a transmission map in [0, 1] over the square that
//! circumscribes the aperture circle, its top row at the image's top. Lens points are drawn
//! with density proportional to the transmission (a piecewise-constant 2D distribution: the
//! rows' marginal table, then the chosen row's conditional one, as in pbrt's
//! `PiecewiseConstant2D`), so the image is the opening's transmission-weighted average and a
//! mask's black cells are never sampled.
//!
//! Each table is searched by a fixed number of halvings (the same for every sample of an
//! image), and the position inside a cell is one subtraction and one division: the GLSL
//! mirror (`shaders/include/camera.glsl`) reads the same table from a storage buffer and gives
//! the same bits.

use glam::Vec2;

/// Larger images are averaged down to at most this many cells a side (the tables then stay
/// under 300 KB).
pub const MAX_SIDE: u32 = 256;

/// Why a transmission map cannot be an aperture.
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum ApertureImageError {
    #[error("the aperture image is empty")]
    Empty,
    #[error("the aperture image is all black: no light passes")]
    Black,
    #[error("the aperture image has {got} values for {columns}x{rows} cells")]
    Size { columns: u32, rows: u32, got: usize },
}

/// A transmission map ready to sample: its cells and the two levels of tables.
#[derive(Clone, Debug, PartialEq)]
pub struct ApertureImage {
    columns: u32,
    rows: u32,
    /// The table the GPU reads too (`table()`): the marginal cumulative distribution over
    /// rows (rows + 1 values, from the top row, 0 first and 1 last), then for each row the
    /// conditional one over its columns (columns + 1 values each, left to right).
    table: Vec<f32>,
    /// The transmission of each cell, row-major from the top-left, after averaging down.
    transmission: Vec<f32>,
}

impl ApertureImage {
    /// The aperture of a `columns` x `rows` transmission map (row-major from the top-left;
    /// values clamped to [0, 1], NaN read as 0), averaged down to at most `MAX_SIDE` a side.
    pub fn new(columns: u32, rows: u32, values: &[f32]) -> Result<Self, ApertureImageError> {
        if columns == 0 || rows == 0 {
            return Err(ApertureImageError::Empty);
        }
        if values.len() != columns as usize * rows as usize {
            return Err(ApertureImageError::Size {
                columns,
                rows,
                got: values.len(),
            });
        }
        let clamped: Vec<f32> = values
            .iter()
            .map(|&v| if v.is_nan() { 0.0 } else { v.clamp(0.0, 1.0) })
            .collect();
        let (columns, rows, transmission) = average_down(columns, rows, &clamped);
        let table = tables(columns, rows, &transmission)?;
        Ok(ApertureImage {
            columns,
            rows,
            table,
            transmission,
        })
    }

    pub fn columns(&self) -> u32 {
        self.columns
    }

    pub fn rows(&self) -> u32 {
        self.rows
    }

    /// The tables, laid out as the GPU's storage buffer holds them (see the field).
    pub fn table(&self) -> &[f32] {
        &self.table
    }

    /// Each cell's transmission, row-major from the top-left.
    pub fn transmission(&self) -> &[f32] {
        &self.transmission
    }

    /// The mean transmission over the square: the share of the square's light the opening
    /// passes.
    pub fn mean_transmission(&self) -> f64 {
        self.transmission.iter().map(|&t| f64::from(t)).sum::<f64>()
            / self.transmission.len() as f64
    }

    /// The cell (column, row) holding unit-square point `p` in [-1, 1]^2 (+y up).
    pub fn cell_of(&self, p: Vec2) -> (u32, u32) {
        let x = ((p.x + 1.0) * 0.5 * self.columns as f32).floor() as i64;
        let y = ((1.0 - p.y) * 0.5 * self.rows as f32).floor() as i64;
        (
            x.clamp(0, i64::from(self.columns) - 1) as u32,
            y.clamp(0, i64::from(self.rows) - 1) as u32,
        )
    }

    /// How far the cells that pass light reach from the centre (the square's half side is 1),
    /// after turning by the angle whose (cos, sin) is `turn` and stretching y by `aspect`.
    pub fn reach(&self, turn: Vec2, aspect: f32) -> f32 {
        let mut reach = 0.0f32;
        for row in 0..self.rows {
            for column in 0..self.columns {
                if self.transmission[(row * self.columns + column) as usize] <= 0.0 {
                    continue;
                }
                for (dx, dy) in [(0, 0), (1, 0), (0, 1), (1, 1)] {
                    let p = Vec2::new(
                        2.0 * (column + dx) as f32 / self.columns as f32 - 1.0,
                        1.0 - 2.0 * (row + dy) as f32 / self.rows as f32,
                    );
                    let q = Vec2::new(turn.x * p.x - turn.y * p.y, turn.y * p.x + turn.x * p.y);
                    reach = reach.max(Vec2::new(q.x, q.y * aspect).length());
                }
            }
        }
        reach
    }

    /// Uniform [0, 1)^2 -> a point of the square [-1, 1]^2 (+y up) with density proportional
    /// to the transmission: `u.y` picks the row by the marginal table, `u.x` the column by the
    /// row's conditional one, each keeping its position inside the chosen cell.
    pub fn sample(&self, u: Vec2) -> Vec2 {
        let rows = self.rows as usize;
        let marginal = &self.table[..rows + 1];
        let (row, v) = invert(marginal, u.y);
        let start = rows + 1 + row * (self.columns as usize + 1);
        let conditional = &self.table[start..start + self.columns as usize + 1];
        let (column, w) = invert(conditional, u.x);
        let x = (column as f32 + w) / self.columns as f32;
        let y = (row as f32 + v) / self.rows as f32;
        Vec2::new(2.0 * x - 1.0, 1.0 - 2.0 * y)
    }
}

/// The interval i of `cdf` (n + 1 non-decreasing values, 0 first, 1 last) with
/// cdf[i] <= u < cdf[i + 1], and where u lies inside it in [0, 1]. A branch-free binary search
/// (the answer stays in [base, base + len), len shrinking to 1): its number of steps depends
/// on n only, whatever u is, and it never lands on an empty interval.
#[inline]
fn invert(cdf: &[f32], u: f32) -> (usize, f32) {
    let mut base = 0;
    let mut len = cdf.len() - 1;
    while len > 1 {
        let half = len / 2;
        base = if cdf[base + half] <= u {
            base + half
        } else {
            base
        };
        len -= half;
    }
    (base, (u - cdf[base]) / (cdf[base + 1] - cdf[base]))
}

/// The marginal and conditional tables of a transmission map (see `ApertureImage::table`).
fn tables(columns: u32, rows: u32, transmission: &[f32]) -> Result<Vec<f32>, ApertureImageError> {
    let (c, r) = (columns as usize, rows as usize);
    let row_sums: Vec<f64> = transmission
        .chunks(c)
        .map(|row| row.iter().map(|&t| f64::from(t)).sum())
        .collect();
    let total: f64 = row_sums.iter().sum();
    if total <= 0.0 {
        return Err(ApertureImageError::Black);
    }
    let mut table = Vec::with_capacity(r + 1 + r * (c + 1));
    table.extend(cumulative(&row_sums, total));
    for (row, &sum) in transmission.chunks(c).zip(&row_sums) {
        if sum > 0.0 {
            let row: Vec<f64> = row.iter().map(|&t| f64::from(t)).collect();
            table.extend(cumulative(&row, sum));
        } else {
            // Never chosen (its marginal interval is empty): uniform, for a valid table.
            table.extend((0..=c).map(|k| k as f32 / c as f32));
        }
    }
    Ok(table)
}

/// 0, then the running sums of `weights` over `total`, the last exactly 1.
fn cumulative(weights: &[f64], total: f64) -> Vec<f32> {
    let mut out = Vec::with_capacity(weights.len() + 1);
    let mut running = 0.0;
    out.push(0.0);
    for &w in weights {
        running += w;
        out.push((running / total) as f32);
    }
    *out.last_mut().expect("one value at least") = 1.0;
    out
}

/// A map of at most `MAX_SIDE` a side: boxes of k x k values averaged (k the smallest factor
/// that fits; boxes cut by the border average what they hold).
fn average_down(columns: u32, rows: u32, values: &[f32]) -> (u32, u32, Vec<f32>) {
    let k = columns.max(rows).div_ceil(MAX_SIDE);
    if k <= 1 {
        return (columns, rows, values.to_vec());
    }
    let (out_c, out_r) = (columns.div_ceil(k), rows.div_ceil(k));
    let mut out = Vec::with_capacity((out_c * out_r) as usize);
    for by in 0..out_r {
        for bx in 0..out_c {
            let (mut sum, mut count) = (0.0f64, 0u32);
            for y in by * k..((by + 1) * k).min(rows) {
                for x in bx * k..((bx + 1) * k).min(columns) {
                    sum += f64::from(values[(y * columns + x) as usize]);
                    count += 1;
                }
            }
            out.push((sum / f64::from(count)) as f32);
        }
    }
    (out_c, out_r, out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_search_finds_the_interval_and_skips_empty_ones() {
        let cdf = [0.0, 0.25, 0.25, 0.25, 0.75, 1.0];
        assert_eq!(invert(&cdf, 0.0), (0, 0.0));
        assert_eq!(invert(&cdf, 0.125), (0, 0.5));
        // 0.25 starts interval 3 (1 and 2 are empty).
        assert_eq!(invert(&cdf, 0.25), (3, 0.0));
        assert_eq!(invert(&cdf, 0.5), (3, 0.5));
        let (i, w) = invert(&cdf, 0.999);
        assert!(i == 4 && (w - 0.996).abs() < 1e-6, "{i} {w}");
        for n in 1..=9u32 {
            let cdf: Vec<f32> = (0..=n).map(|k| k as f32 / n as f32).collect();
            for k in 0..n {
                let u = (k as f32 + 0.5) / n as f32;
                assert_eq!(invert(&cdf, u).0, k as usize, "n {n}, u {u}");
            }
        }
    }

    #[test]
    fn bad_maps_are_refused() {
        assert_eq!(
            ApertureImage::new(0, 3, &[]),
            Err(ApertureImageError::Empty)
        );
        assert_eq!(
            ApertureImage::new(2, 2, &[0.0, -1.0, f32::NAN, 0.0]),
            Err(ApertureImageError::Black)
        );
        assert!(matches!(
            ApertureImage::new(2, 2, &[1.0]),
            Err(ApertureImageError::Size { got: 1, .. })
        ));
    }

    #[test]
    fn large_maps_are_averaged_down() {
        let (c, r) = (600u32, 300u32);
        let values: Vec<f32> = (0..c * r).map(|i| ((i % c) < 300) as u32 as f32).collect();
        let image = ApertureImage::new(c, r, &values).unwrap();
        assert_eq!((image.columns(), image.rows()), (200, 100));
        assert!((image.mean_transmission() - 0.5).abs() < 1e-6);
    }

    /// A map with a gradient, a hole and empty rows: each cell's share of the samples follows
    /// its transmission (chi-square within 5 standard deviations of its degrees of freedom),
    /// and black cells get none.
    #[test]
    fn samples_follow_the_transmission() {
        let (c, r) = (12u32, 10u32);
        let values: Vec<f32> = (0..r)
            .flat_map(|y| {
                (0..c).map(move |x| match (x, y) {
                    (_, 0) | (_, 9) => 0.0,
                    (4..=6, 4..=5) => 0.0,
                    _ => 0.1 + 0.9 * x as f32 / (c - 1) as f32,
                })
            })
            .collect();
        let image = ApertureImage::new(c, r, &values).unwrap();
        let samples = 200_000u32;
        let mut counts = vec![0u32; (c * r) as usize];
        let mut next = super::super::uniform_stream();
        for _ in 0..samples {
            let p = image.sample(Vec2::new(next(), next()));
            assert!(p.x.abs() <= 1.0 && p.y.abs() <= 1.0, "{p}");
            let (x, y) = image.cell_of(p);
            counts[(y * c + x) as usize] += 1;
        }
        let total: f64 = values.iter().map(|&v| f64::from(v)).sum();
        let (mut chi2, mut dof) = (0.0, 0);
        for (cell, &count) in counts.iter().enumerate() {
            if values[cell] == 0.0 {
                assert_eq!(count, 0, "black cell {cell} was sampled");
                continue;
            }
            let expected = f64::from(values[cell]) / total * f64::from(samples);
            chi2 += (f64::from(count) - expected).powi(2) / expected;
            dof += 1;
        }
        let bound = f64::from(dof) + 5.0 * (2.0 * f64::from(dof)).sqrt();
        assert!(chi2 < bound, "chi-square {chi2:.1} over {dof} cells");
    }
}
