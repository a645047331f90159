package dev.motionfusion.core.io

import java.io.BufferedInputStream
import java.io.InputStream
import java.util.zip.GZIPInputStream

/** Opening byte inputs the same way everywhere: gzip detected by its magic bytes (not the name) and guarded. */
internal object Inputs {
    private const val GZIP_MAGIC_1 = 0x1f
    private const val GZIP_MAGIC_2 = 0x8b
    const val BUFFER_BYTES: Int = 1 shl 16

    /** [input] decompressed through [guard] when it starts with the gzip magic bytes; [name] names it in errors. */
    fun maybeGunzip(input: InputStream, name: String, guard: CompressionGuard): InputStream {
        val buffered = if (input.markSupported()) input else BufferedInputStream(input, BUFFER_BYTES)
        buffered.mark(2)
        val b1 = buffered.read()
        val b2 = buffered.read()
        buffered.reset()
        if (b1 != GZIP_MAGIC_1 || b2 != GZIP_MAGIC_2) return buffered
        try {
            return guard.wrap({ GZIPInputStream(buffered, BUFFER_BYTES) }, name)
        } catch (e: Throwable) {
            buffered.close()
            throw e
        }
    }
}
