/*
 * The one guard of every compressed input (gzip files, zip entries): caps on the decompressed
 * bytes of one file and of all files read for one pass over a recording, and the one place where
 * broken compressed data becomes a DataFormatException naming the file and the reason.
 */
package dev.motionfusion.core.io

import java.io.EOFException
import java.io.FilterInputStream
import java.io.IOException
import java.io.InputStream
import java.util.zip.ZipException

/**
 * Caps on decompressed bytes: [maxEntryBytes] for one compressed file (a .gz or one zip entry),
 * [maxTotalBytes] for all compressed files of one recording read once. The defaults hold a day
 * of recording (a session at 500 Hz with four streams is about 8 GB a day of CSV); a bomb stops
 * at the cap instead of running for hours.
 */
public data class InputLimits(
    val maxEntryBytes: Long = DEFAULT_ENTRY_BYTES,
    val maxTotalBytes: Long = DEFAULT_TOTAL_BYTES,
) {
    init {
        require(maxEntryBytes > 0 && maxTotalBytes >= maxEntryBytes) { "limits must be positive, total ≥ per file: $this" }
    }

    public companion object {
        public const val DEFAULT_ENTRY_BYTES: Long = 16L shl 30
        public const val DEFAULT_TOTAL_BYTES: Long = 64L shl 30

        /** Limits with [perFile] bytes per compressed file and four times that in total. */
        @JvmStatic
        public fun perFile(perFile: Long): InputLimits = InputLimits(perFile, if (perFile > Long.MAX_VALUE / 4) Long.MAX_VALUE else 4 * perFile)
    }
}

/** Counts decompressed bytes against [limits] (the total over every stream it wrapped since [reset]). */
internal class CompressionGuard(val limits: InputLimits) {
    private var total = 0L

    fun reset() {
        total = 0L
    }

    /** [decompressing] (a GZIPInputStream or zip entry stream) counted and with its failures mapped to DataFormatException naming [name]. */
    fun wrap(decompressing: () -> InputStream, name: String): InputStream = GuardedStream(mapped(name) { decompressing() }, name)

    private inner class GuardedStream(inner: InputStream, private val name: String) : FilterInputStream(inner), Decompressed {
        private var count = 0L

        override fun read(): Int {
            val b = mapped(name) { super.read() }
            if (b >= 0) add(1)
            return b
        }

        override fun read(b: ByteArray, off: Int, len: Int): Int {
            val n = mapped(name) { super.read(b, off, len) }
            if (n > 0) add(n)
            return n
        }

        override fun skip(n: Long): Long {
            val s = mapped(name) { super.skip(n) }
            add(s)
            return s
        }

        private fun add(n: Number) {
            count += n.toLong()
            total += n.toLong()
            if (count > limits.maxEntryBytes) {
                throw DataFormatException(name, 0, 0, "decompresses to more than ${limits.maxEntryBytes} bytes, the limit for one file (a zip bomb? raise it with --max-uncompressed)", OverLimit())
            }
            if (total > limits.maxTotalBytes) {
                throw DataFormatException(name, 0, 0, "the recording decompresses to more than ${limits.maxTotalBytes} bytes in total (a zip bomb? raise it with --max-uncompressed)", OverLimit())
            }
        }
    }

    private inline fun <T> mapped(name: String, block: () -> T): T = try {
        block()
    } catch (e: ZipException) {
        throw DataFormatException(name, 0, 0, "corrupt compressed data: ${e.message}", e)
    } catch (e: EOFException) {
        throw DataFormatException(name, 0, 0, "compressed data ends early: ${e.message}", e)
    } catch (e: IOException) {
        if (e.javaClass.name.startsWith("java.util.zip")) throw DataFormatException(name, 0, 0, "corrupt compressed data: ${e.message}", e)
        throw e
    }
}

/** A stream of decompressed data: its integrity check (CRC-32) comes at its end, after any data it damaged. */
internal interface Decompressed

/** The cause of a limit's DataFormatException: sniffing a format must pass it on, not take it for "not this kind". */
internal class OverLimit : RuntimeException(null, null, false, false)
