"""A hint to the processor to bring one array element into the cache before it is read.

A pass whose reads jump about memory (a triangle's corners, its neighbours' rows) waits for
each miss in turn when the loop body is too long for the processor to run ahead into the next
iterations by itself; asking for the rows of a triangle some iterations ahead overlaps those
waits. The hint never faults and changes no result, so an index out of range only wastes it.
"""

from __future__ import annotations

from llvmlite import ir
from numba import types
from numba.core import cgutils
from numba.extending import intrinsic

__all__ = ["prefetch"]


@intrinsic
def prefetch(typingctx, array, index):
    """Ask for the cache line of ``array[index]`` (of row ``index`` of a 2-D array) to be read
    soon (LLVM's ``llvm.prefetch``: a read, kept in every cache level)."""
    if not isinstance(array, types.Array) or array.ndim not in (1, 2) or not isinstance(index, types.Integer):
        return None
    signature = types.void(array, index)

    def codegen(context, builder, sig, args):
        array_type, index_type = sig.args
        data = context.make_array(array_type)(context, builder, args[0])
        at = context.cast(builder, args[1], index_type, types.intp)
        indices = [at] if array_type.ndim == 1 else [at, context.get_constant(types.intp, 0)]
        pointer = cgutils.get_item_pointer(context, builder, array_type, data, indices, wraparound=False)
        i32 = ir.IntType(32)
        byte_pointer = ir.IntType(8).as_pointer()
        hint = cgutils.get_or_insert_function(builder.module, ir.FunctionType(ir.VoidType(), [byte_pointer, i32, i32, i32]),
                                              "llvm.prefetch.p0")
        builder.call(hint, [builder.bitcast(pointer, byte_pointer), i32(0), i32(3), i32(1)])   # read, kept, data
        return context.get_dummy_value()

    return signature, codegen
