// ASCII STL: keywords in any case, one per line; what follows solid, facet, outer, endloop,
// endfacet and endsolid on their line is not read (names, normals):
//     solid NAME / facet normal nx ny nz / outer loop / vertex x y z (three, nothing after) /
//     endloop / endfacet / ... / endsolid NAME (then another solid, or the end)
#pragma once
#include <cstring>

#include "text/lexer.hpp"

namespace inertia::text {

// A corner equal (bit for bit) to one of the recently read corners (a direct-mapped table of
// 2^10 slots by hash, 32 KB) is not stored again: STL repeats a vertex for each facet around it,
// mostly in nearby facets, so the vertices are about a fifth of the corners (less to weld), and
// vertices[faces] are the file's corners.
inline Mesh read_ascii_stl(const uint8_t *d, size_t n) {
    enum { OUTSIDE, SOLID, FACET };
    constexpr int slot_bits = 10;
    Lexer t{d, n, false};
    Mesh m;
    m.faces.reserve(3 * (n / 128 + 16));  // (exporters write 200-300 bytes a facet; only touched pages cost)
    m.vertices.reserve(3 * (n / 256 + 16));
    struct Slot {
        uint64_t bits[3];
        int64_t row = -1;
    };
    std::vector<Slot> recent(size_t(1) << slot_bits);
    int state = OUTSIDE, corners = 0;
    int64_t corner[3] = {0, 0, 0};
    size_t last = 0, i = 0;
    auto fail = [&](TextError e) { return m.error = e, std::move(m); };
    while (i < n) {
        const size_t line = i;
        i = t.skip_blanks(i);
        if (i >= n) break;
        if (d[i] == '\n') {
            ++i;
            continue;
        }
        const size_t j = t.word_end(i);
        last = line;
        if (t.is_word(i, j, "vertex")) {
            if (state != FACET) return fail(t.error(UNEXPECTED, line, i, state));
            if (corners == 3) return fail(t.error(FACET_SIZE, line, 0, 4));
            double c[3];
            i = j;
            if (!t.coordinates(i, line, c, m.error)) return m;
            i = t.skip_blanks(i);
            if (!t.line_ends(i)) return fail(t.error(EXTRA_TOKENS, line, i));
            Slot s;
            std::memcpy(s.bits, c, sizeof c);
            const uint64_t h = s.bits[0] * 0x9E3779B97F4A7C15ull ^ s.bits[1] * 0xC2B2AE3D27D4EB4Full ^
                               s.bits[2] * 0x165667B19E3779F9ull;
            Slot &r = recent[(h ^ (h >> 29)) >> (64 - slot_bits)];
            if (r.row < 0 || std::memcmp(r.bits, s.bits, sizeof s.bits) != 0) {
                s.row = int64_t(m.vertices.size() / 3);
                r = s;
                m.vertices.insert(m.vertices.end(), c, c + 3);
            }
            corner[corners++] = r.row;
            continue;
        }
        if (t.is_word(i, j, "facet") && state == SOLID) {
            state = FACET, corners = 0;
        } else if (t.is_word(i, j, "endfacet") && state == FACET) {
            if (corners != 3) return fail(t.error(FACET_SIZE, line, 0, corners));
            m.faces.insert(m.faces.end(), corner, corner + 3);
            state = SOLID;
        } else if ((t.is_word(i, j, "outer") || t.is_word(i, j, "endloop")) && state == FACET) {
        } else if (t.is_word(i, j, "solid") && state == OUTSIDE) {
            state = SOLID;
        } else if (t.is_word(i, j, "endsolid") && state == SOLID) {
            state = OUTSIDE;
        } else {
            return fail(t.error(UNEXPECTED, line, i, state));
        }
        i = t.end_of_line(j) + 1;
    }
    if (state != OUTSIDE) m.error = t.error(TRUNCATED, last, 0, state);
    return m;
}

}  // namespace inertia::text
