// Exact welding: rows of equal coordinates grouped in one hash pass, each group numbered in
// order of first appearance and standing for its lowest index; compaction of unused vertices.
#pragma once
#include <algorithm>
#include <cstdint>
#include <cstring>
#include <vector>

#include "topology/hash.hpp"

namespace inertia::topology {

// A mesh as flat arrays: v (3 V) float64, f (3 F) vertex indices.
struct Mesh {
    Vec<double> v;
    Vec<int64_t> f;
    size_t n_vertices() const { return v.size() / 3; }
    size_t n_faces() const { return f.size() / 3; }
};

// The table slot hash of a row's keys: 64-bit words as they are, 32-bit ones packed two to a word.
inline uint64_t key_hash(const uint64_t *k) { return mix3(k[0], k[1], k[2]); }
inline uint64_t key_hash(const uint32_t *k) { return mix3(k[0] | uint64_t(k[1]) << 32, k[2], 0x5BD1E995u); }

// group[i]: i's group, numbered in order of first appearance; first[g]: the lowest index in g.
template <class I>
struct Groups {
    Vec<I> group, first;
    I count = 0;
};

// Group n rows by their keys: three unsigned words, each the bits of one coordinate with -0.0
// folded onto 0.0, so that equal bits are equal coordinates.  `load(i, k)` writes row i's keys.
// A row with a NaN or infinity (all exponent bits set) is a group of its own.  The table holds
// group numbers, a slot for each row at least, and doubles when the groups fill half of it.
template <class I, class K, class Load>
Groups<I> weld_groups(size_t n, Load load) {
    constexpr K expo = sizeof(K) == 8 ? K(0x7FF0000000000000ull) : K(0x7F800000u);
    auto finite = [&](const K *k) { return (k[0] & expo) != expo && (k[1] & expo) != expo && (k[2] & expo) != expo; };
    Groups<I> out;
    out.group.resize(n);
    out.first.resize(n);
    Vec<K> keys(3 * n);
    uint64_t cap = capacity(std::max<uint64_t>(8, (n + 3) / 4)), mask = cap - 1;
    Vec<I> table(cap, I(-1));
    I ng = 0;
    // a table beyond the caches: the slot of row i + ahead is fetched from memory while row i is placed
    const size_t ahead = cap * sizeof(I) > (size_t(1) << 20) ? 16 : n;
    for (size_t i = 0; i < n; ++i) {
        if (i + ahead < n) {
            K later[3];
            load(i + ahead, later);
            __builtin_prefetch(&table[key_hash(later) & mask]);
        }
        K *k = &keys[3 * size_t(ng)];   // the keys of a new group, if row i starts one
        load(i, k);
        I g = ng;
        if (finite(k)) {
            for (uint64_t slot = key_hash(k) & mask;; slot = (slot + 1) & mask) {
                const I t = table[slot];
                if (t < 0) {
                    table[slot] = ng;
                    break;
                }
                const K *c = &keys[3 * size_t(t)];
                if (c[0] == k[0] && c[1] == k[1] && c[2] == k[2]) {
                    g = t;
                    break;
                }
            }
        }
        out.group[i] = g;
        if (g != ng) continue;
        out.first[ng++] = I(i);
        if (uint64_t(2 * ng) > cap) {   // keep the load <= 1/2: double the table, re-insert the groups
            cap *= 2;
            mask = cap - 1;
            table.assign(cap, I(-1));
            for (I t = 0; t < ng; ++t) {
                const K *c = &keys[3 * size_t(t)];
                if (!finite(c)) continue;
                uint64_t slot = key_hash(c) & mask;
                while (table[slot] >= 0) slot = (slot + 1) & mask;
                table[slot] = t;
            }
        }
    }
    out.count = ng;
    return out;
}

// Groups of the rows of v (n, 3) float64 by exactly equal coordinates (-0.0 == 0.0, unless
// SignedZeros: then equal bits).
template <bool SignedZeros = false>
inline Groups<int64_t> weld_rows(const double *v, size_t n) {
    return weld_groups<int64_t, uint64_t>(n, [v](size_t i, uint64_t *k) {
        for (int c = 0; c < 3; ++c) {
            const double x = SignedZeros ? v[3 * i + c] : v[3 * i + c] + 0.0;
            std::memcpy(&k[c], &x, 8);
        }
    });
}

// rep[i]: the lowest index of a row equal to row i (as weld_rows; a row with NaN or inf: i).
template <bool SignedZeros = false>
inline Vec<int64_t> weld_map(const double *v, size_t n) {
    const Groups<int64_t> g = weld_rows<SignedZeros>(v, n);
    Vec<int64_t> rep(n);
    for (size_t i = 0; i < n; ++i) rep[i] = g.first[size_t(g.group[i])];
    return rep;
}

// Drop the vertices no face uses and renumber the faces, keeping the vertices' order.
// `id[i]` is vertex i's group (identity when null), n_ids the number of groups, `coords_of[g]`
// the vertex whose coordinates group g takes.
template <class I>
Mesh compact_groups(const double *v, const int64_t *f, size_t nf, const I *id, size_t n_ids, const I *coords_of) {
    Vec<int64_t> new_id(n_ids, -1);
    auto at = [id](int64_t i) { return id ? int64_t(id[i]) : i; };
    for (size_t i = 0; i < 3 * nf; ++i) new_id[at(f[i])] = 0;
    int64_t kept = 0;
    for (auto &x : new_id)
        if (x == 0) x = kept++;
    Mesh out;
    out.v.resize(3 * size_t(kept));
    for (size_t g = 0; g < n_ids; ++g)
        if (new_id[g] >= 0) {
            const size_t i = coords_of ? size_t(coords_of[g]) : g;
            std::copy(v + 3 * i, v + 3 * i + 3, &out.v[3 * size_t(new_id[g])]);
        }
    out.f.resize(3 * nf);
    for (size_t i = 0; i < 3 * nf; ++i) out.f[i] = new_id[at(f[i])];
    return out;
}

// Weld equal rows and drop unreferenced vertices: compact(v, weld_map(v)[f]) in one pass each.
inline Mesh weld_compact(const double *v, size_t nv, const int64_t *f, size_t nf) {
    const Groups<int64_t> g = weld_rows(v, nv);
    return compact_groups<int64_t>(v, f, nf, g.group.data(), size_t(g.count), g.first.data());
}

}  // namespace inertia::topology
