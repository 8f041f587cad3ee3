//! Insertion orders for the incremental engines (both dimensions): biased
//! randomised insertion (BRIO) along a space-filling curve.

/// Deterministic xorshift: the same input gives the same triangulation.
pub(super) struct Rng(pub(super) u64);

impl Rng {
    pub(super) fn next(&mut self) -> u64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        self.0
    }
}

/// The points but `skip` in BRIO order by their curve keys: a shuffle,
/// then rounds of doubling size from 64, each sorted by key (both
/// dimensions' engines).
pub(super) fn brio_order(key: &[u64], skip: &[u32]) -> Vec<u32> {
    let mut order: Vec<u32> = (0..key.len() as u32)
        .filter(|v| !skip.contains(v))
        .collect();
    let mut rng = Rng(0x9e37_79b9_7f4a_7c15);
    for i in (1..order.len()).rev() {
        order.swap(i, (rng.next() % (i as u64 + 1)) as usize);
    }
    let (mut start, mut size) = (0, 64);
    while start < order.len() {
        let end = (start + size).min(order.len());
        order[start..end].sort_unstable_by_key(|&i| key[i as usize]);
        start = end;
        size *= 2;
    }
    order
}
