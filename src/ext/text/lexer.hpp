// Words and numbers of mesh text (ASCII STL, OBJ), byte by byte.  Lines end at LF; space, tab,
// CR, VT and FF separate words; in OBJ a backslash before the LF (or CR LF) joins the next line.
#pragma once
#include <charconv>
#include <cmath>
#include <cstring>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

namespace inertia::text {

// Error kinds, as the Python side (geometry._text_readers) words them.
enum Kind : int {
    OK,
    BAD_NUMBER,    // token: the word that is no number
    FEW_COORDS,    // count: coordinates found
    EXTRA_TOKENS,  // token: the word after the 3 coordinates of an STL vertex
    UNEXPECTED,    // token: the STL keyword; count: where (0 outside a solid, 1 in a solid, 2 in a facet)
    FACET_SIZE,    // count: the vertices of the facet
    TRUNCATED,     // count: where the STL ends, as UNEXPECTED
    BAD_REF,       // token: the OBJ face vertex
    ZERO_INDEX,    // token: the OBJ face vertex
    FEW_REFS,      // count: the vertices of the face
    INDEX_RANGE,   // token: the OBJ face vertex; count: vertices defined above it (negative) or in the file
};

// Where and why a file is malformed (offsets into the text; token_end == token when no token).
struct TextError {
    int kind = OK;
    size_t line = 0, token = 0, token_end = 0;
    int64_t count = 0;
};

// What a reader gives: vertices (V, 3) and faces (F, 3) flat, row by row, or the first error.
struct Mesh {
    std::vector<double> vertices;
    std::vector<int64_t> faces;
    TextError error;
};

inline bool blank(uint8_t c) { return c == ' ' || (c >= 9 && c <= 13 && c != '\n'); }
inline bool digit(uint8_t c) { return c >= '0' && c <= '9'; }

struct Lexer {
    const uint8_t *d;
    size_t n;
    bool joins;  // OBJ: backslash-newline continues the line

    // Length of a continuation (backslash, optional CR, LF) at i, else 0.
    size_t continued(size_t i) const {
        if (!joins || i >= n || d[i] != '\\') return 0;
        if (i + 1 < n && d[i + 1] == '\n') return 2;
        return i + 2 < n && d[i + 1] == '\r' && d[i + 2] == '\n' ? 3 : 0;
    }
    size_t skip_blanks(size_t i) const {
        while (i < n) {
            if (blank(d[i])) ++i;
            else if (size_t k = continued(i)) i += k;
            else break;
        }
        return i;
    }
    bool line_ends(size_t i) const { return i >= n || d[i] == '\n'; }
    // The LF ending the (logical) line that holds i, or n.
    size_t end_of_line(size_t i) const {
        for (; i < n; ++i) {
            const void *lf = std::memchr(d + i, '\n', n - i);
            if (lf == nullptr) return n;
            i = size_t(static_cast<const uint8_t *>(lf) - d);
            size_t j = i;
            if (j > 0 && d[j - 1] == '\r') --j;
            if (!joins || j == 0 || d[j - 1] != '\\') return i;
        }
        return n;
    }
    // True when i ends a word: a separator, LF, the end, a continuation (or '#', with hash).
    bool word_ends(size_t i, bool hash = false) const {
        return i >= n || d[i] == '\n' || blank(d[i]) || continued(i) || (hash && d[i] == '#');
    }
    size_t word_end(size_t i, bool hash = false) const {
        while (!word_ends(i, hash)) ++i;
        return i;
    }
    // The word at i spelled `lower` in any case.
    bool is_word(size_t i, size_t j, const char *lower) const {
        for (; i < j; ++i, ++lower)
            if (*lower == 0 || (d[i] | 32) != static_cast<uint8_t>(*lower)) return false;
        return *lower == 0;
    }

    // The decimal number at i, read correctly rounded (as strtod): [+-]digits[.digits][e[+-]digits]
    // ('.5' and '5.' too) or nan, inf, infinity in any case.  Returns its end, or i when no number
    // starts there (the caller checks that a word ends at the end).  Up to 19 significant digits
    // making an integer <= 2^53 with a power of ten within 1e+-22 is one exact integer times or
    // over one exact power: a single rounding (Clinger's fast path); the rest goes to
    // std::from_chars, exact for any input.
    size_t number(size_t i, double &value) const {
        static constexpr double p10[] = {1e0,  1e1,  1e2,  1e3,  1e4,  1e5,  1e6,  1e7,  1e8,  1e9,  1e10, 1e11,
                                         1e12, 1e13, 1e14, 1e15, 1e16, 1e17, 1e18, 1e19, 1e20, 1e21, 1e22};
        const size_t at = i;
        const bool neg = i < n && d[i] == '-';
        if (i < n && (d[i] == '-' || d[i] == '+')) ++i;
        const size_t start = i;
        uint64_t mant = 0;
        int64_t sig = 0, int_sig = 0, lead_zeros = 0;  // significant digits, those before the point, zeros before them
        int64_t frac = 0, digits = 0;
        auto take = [&](uint8_t c) {
            if (sig == 0 && c == '0') return;
            if (sig < 19) mant = mant * 10 + (c - '0');
            ++sig;
        };
        for (; i < n && digit(d[i]); ++i, ++digits) take(d[i]);
        int_sig = sig;
        if (i < n && d[i] == '.') {
            for (++i; i < n && digit(d[i]); ++i, ++digits, ++frac) {
                lead_zeros += sig == 0 && d[i] == '0';
                take(d[i]);
            }
        } else if (digits == 0) {  // no digit, no point: nan, inf or infinity?
            const double inf = std::numeric_limits<double>::infinity();
            size_t j = i + 3 <= n && is_word(i, i + 3, "nan") ? i + 3 : 0;
            if (j) value = std::numeric_limits<double>::quiet_NaN();
            else if (i + 8 <= n && is_word(i, i + 8, "infinity")) j = i + 8, value = inf;
            else if (i + 3 <= n && is_word(i, i + 3, "inf")) j = i + 3, value = inf;
            if (j == 0) return at;
            value = std::copysign(value, neg ? -1.0 : 1.0);
            return j;
        }
        if (digits == 0) return at;
        int64_t e = 0;
        if (i < n && (d[i] | 32) == 'e') {
            ++i;
            const bool eneg = i < n && d[i] == '-';
            if (i < n && (d[i] == '-' || d[i] == '+')) ++i;
            const size_t e0 = i;
            for (; i < n && digit(d[i]); ++i)
                if (e < 100000000000000000) e = e * 10 + (d[i] - '0');  // (saturates far beyond any double)
            if (i == e0) return at;
            if (eneg) e = -e;
        }
        const int64_t e10 = e - frac;
        if (sig == 0) {
            value = 0.0;
        } else if (sig <= 19 && mant <= (uint64_t(1) << 53) && e10 >= -22 && e10 <= 22) {
            value = e10 >= 0 ? double(mant) * p10[e10] : double(mant) / p10[-e10];
        } else {
            auto r = std::from_chars(reinterpret_cast<const char *>(d + start), reinterpret_cast<const char *>(d + i),
                                     value, std::chars_format::general);
            if (r.ptr != reinterpret_cast<const char *>(d + i)) return at;  // (the grammar above is a subset)
            if (r.ec == std::errc::result_out_of_range)  // beyond the largest double, or below half the least
                value = (int_sig > 0 ? int_sig - 1 : -lead_zeros - 1) + e > 0 ? std::numeric_limits<double>::infinity()
                                                                               : 0.0;
        }
        value = neg ? -value : value;
        return i;
    }

    // The error of `kind` on the line at `line`; a face vertex (OBJ) ends at a '#' too.
    TextError error(int kind, size_t line, size_t token = 0, int64_t count = 0) const {
        const bool word = kind == BAD_NUMBER || kind == EXTRA_TOKENS || kind == UNEXPECTED || kind == BAD_REF ||
                          kind == ZERO_INDEX || kind == INDEX_RANGE;
        return {kind, line, token, word ? word_end(token, kind >= BAD_REF) : token, count};
    }

    // The three coordinates of a vertex line from i into c (i moves past them), or an error.
    bool coordinates(size_t &i, size_t line, double *c, TextError &err) const {
        for (int k = 0; k < 3; ++k) {
            i = skip_blanks(i);
            if (line_ends(i)) return err = error(FEW_COORDS, line, 0, k), false;
            const size_t end = number(i, c[k]);
            if (end == i || !word_ends(end)) return err = error(BAD_NUMBER, line, i), false;
            i = end;
        }
        return true;
    }
};

}  // namespace inertia::text
