// grammar/domain_comment.hpp — the domain a RANOK script states in its header comment.
//
// Why: RANOK kept a scene's box outside the language, and its scripts record it in a comment
// near the top, as half-extents (`//x=8, y=5,z=8;`, `//x : 3,5 ; y : 3,5 ; z : 3,5` with a
// decimal comma), as ranges (`//X=[0;7] Y=[0;7] Z=[0;7]`), or as two lists, half-extents
// then the centre (`//x=12` `//y=37,5` ... then `//x=0` ... `//z=140`). This file only reads
// that text; interp decides whether it sets the domain (header_domain.hpp).
#pragma once

#include "grammar/source.hpp"

#include <array>
#include <optional>

namespace fortu {

struct DomainComment {
    /// Per axis (x, y, z by the comment's letters): {min, max}, or nullopt when not given.
    std::array<std::optional<std::array<double, 2>>, 3> ranges;
    /// The first comment line that gave a value (for the note pointing at it).
    SourceRange where;
};

/// Reads the header: the lines before the first statement other than ARGUMENT (blank lines,
/// `//` comments, ARGUMENT/ARG). A comment line counts when it holds only axis entries —
/// `x = 3`, `y : 3,5` (half-extent, `,` or `.` as decimal point), `z=[0;7]` (a range) —
/// separated by spaces, `,` or `;`. The first entry of an axis is its half-extent or range;
/// a second list of half-extent entries is the centre. nullopt when no line counts or a
/// half-extent is not positive.
std::optional<DomainComment> read_domain_comment(const SourceFile& source);

}  // namespace fortu
