package dev.motionfusion.core.io

import java.io.BufferedInputStream
import java.io.BufferedReader
import java.io.InputStream
import java.io.InputStreamReader
import java.nio.charset.StandardCharsets
import java.nio.file.Files
import java.nio.file.Path
import java.util.zip.GZIPInputStream

/** Opening text inputs the same way everywhere: UTF-8, optional gzip (detected by its magic bytes, not the name). */
internal object Inputs {
    private const val GZIP_MAGIC_1 = 0x1f
    private const val GZIP_MAGIC_2 = 0x8b
    private const val BUFFER_BYTES = 1 shl 16

    /** [input] decompressed when it starts with the gzip magic bytes. */
    fun maybeGunzip(input: InputStream): InputStream {
        val buffered = if (input.markSupported()) input else BufferedInputStream(input, BUFFER_BYTES)
        buffered.mark(2)
        val b1 = buffered.read()
        val b2 = buffered.read()
        buffered.reset()
        return if (b1 == GZIP_MAGIC_1 && b2 == GZIP_MAGIC_2) {
            BufferedInputStream(GZIPInputStream(buffered, BUFFER_BYTES), BUFFER_BYTES)
        } else {
            buffered
        }
    }

    fun reader(input: InputStream): BufferedReader =
        BufferedReader(InputStreamReader(maybeGunzip(input), StandardCharsets.UTF_8), BUFFER_BYTES)

    fun reader(path: Path): BufferedReader = reader(Files.newInputStream(path))
}
