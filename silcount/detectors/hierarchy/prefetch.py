"""``prefetch``: ask the processor for a row's memory before it is read (``llvm.prefetch``).

Used by the hierarchies' compiled query (:mod:`.walk`) and build
(:mod:`.build`, and the schemes' keys through :func:`.morton.plane_sum`),
whose loops read rows of large arrays in an order the processor cannot predict.  A prefetch
changes no value, only when memory arrives.
"""

from __future__ import annotations

from llvmlite import ir
from numba import types
from numba.core import cgutils
from numba.extending import intrinsic

ROWS_AHEAD = 32  # in the build's loops over edges: the row of the edge this many ahead is asked for


@intrinsic
def prefetch(typingctx, arr, row):  # pragma: no cover - compiled
    """Ask the processor for the cache line holding ``arr[row, 0]`` (``arr[row]`` of a 1-D array), without waiting
    for it: ``llvm.prefetch`` (read, high locality, data).  ``row`` must be a signed 64-bit integer."""
    sig = types.void(arr, row)

    def codegen(context, builder, signature, args):
        aryty = signature.args[0]
        ary = context.make_array(aryty)(context, builder, args[0])
        idx = [args[1]] + [context.get_constant(types.intp, 0)] * (aryty.ndim - 1)
        ptr = cgutils.get_item_pointer(context, builder, aryty, ary, idx)
        i8p, i32 = ir.PointerType(ir.IntType(8)), ir.IntType(32)
        fn = cgutils.get_or_insert_function(builder.module, ir.FunctionType(ir.VoidType(), [i8p, i32, i32, i32]),
                                            "llvm.prefetch.p0i8")  # fmt: skip
        builder.call(fn, [builder.bitcast(ptr, i8p), ir.Constant(i32, 0), ir.Constant(i32, 3), ir.Constant(i32, 1)])
        return context.get_dummy_value()

    return sig, codegen


__all__ = ["prefetch", "ROWS_AHEAD"]
