package dev.motionfusion.core.io

import java.io.BufferedInputStream
import java.io.EOFException
import java.io.InputStream
import java.nio.file.FileSystemException
import java.nio.file.Files
import java.nio.file.Path
import java.util.zip.CRC32
import java.util.zip.DataFormatException as InflaterDataException
import java.util.zip.Inflater
import java.util.zip.ZipException

/** Opening byte inputs the same way everywhere: gzip detected by its magic bytes (not the name) and guarded. */
internal object Inputs {
    private const val GZIP_MAGIC_1 = 0x1f
    private const val GZIP_MAGIC_2 = 0x8b
    const val BUFFER_BYTES: Int = 1 shl 16

    /** True for "-", which names standard input. */
    fun isStandardInput(path: Path): Boolean = path.toString() == "-"

    /** How [path] is named in messages: as given, standard input as "standard input". */
    fun shown(path: Path): String = if (isStandardInput(path)) "standard input" else path.toString()

    /**
     * The one file [path] for one pass: a regular file, a pipe, a FIFO, a device, or standard
     * input ("-", not closed with the stream). A folder is an error naming it.
     */
    fun openFile(path: Path): InputStream {
        if (isStandardInput(path)) return object : java.io.FilterInputStream(System.`in`) {
            override fun close() {}
        }
        if (Files.isDirectory(path)) throw FileSystemException(path.toString(), null, "is a folder; a file is expected here")
        val input = AtomicFiles.named(path) { Files.newInputStream(path) }
        if (Files.isRegularFile(path)) return input
        // A pipe or device: its channel cannot tell a position, so available() and skip() would
        // fail with "Illegal seek"; they are answered without it.
        return object : java.io.FilterInputStream(input) {
            override fun available(): Int = 0
            override fun skip(n: Long): Long {
                var left = n
                while (left > 0 && read() >= 0) left--
                return n - left
            }
        }
    }

    /** [input] decompressed through [guard] when it starts with the gzip magic bytes; [name] names it in errors. */
    fun maybeGunzip(input: InputStream, name: String, guard: CompressionGuard): InputStream {
        val buffered = if (input.markSupported()) input else BufferedInputStream(input, BUFFER_BYTES)
        buffered.mark(2)
        val b1 = buffered.read()
        val b2 = buffered.read()
        buffered.reset()
        if (b1 != GZIP_MAGIC_1 || b2 != GZIP_MAGIC_2) return buffered
        try {
            return guard.wrap({ GunzipStream(buffered) }, name)
        } catch (e: Throwable) {
            buffered.close()
            throw e
        }
    }

    /**
     * The members of a gzip file (RFC 1952; several members are one file, as `cat a.gz b.gz`
     * makes) decompressed in turn, each checked against its trailer (CRC-32 and length). After
     * a member comes another member or the end; only zero bytes (padding) may follow the last.
     * java.util.zip.GZIPInputStream is not used: it ends silently at a member whose header is
     * damaged, and at the end of what a pipe had ready, which would replay part of a file as if
     * it were all of it.
     */
    private class GunzipStream(private val input: InputStream) : InputStream() {
        private val inflater = Inflater(true)
        private val crc = CRC32()
        private val buf = ByteArray(BUFFER_BYTES)
        private var bufLen = 0
        private var bufPos = 0
        /** Bytes of the file before buf[0]. */
        private var consumed = 0L
        private var member = 0
        private var done = false

        init {
            startMember()
        }

        override fun read(): Int {
            val one = ByteArray(1)
            return if (read(one, 0, 1) < 0) -1 else one[0].toInt() and 0xff
        }

        override fun read(b: ByteArray, off: Int, len: Int): Int {
            if (len == 0) return 0
            while (!done) {
                val n = try {
                    inflater.inflate(b, off, len)
                } catch (e: InflaterDataException) {
                    throw ZipException("member $member: ${e.message}")
                }
                if (n > 0) {
                    crc.update(b, off, n)
                    return n
                }
                when {
                    inflater.finished() -> endMember()
                    inflater.needsDictionary() -> throw ZipException("member $member: needs a preset dictionary")
                    inflater.needsInput() -> {
                        if (!fill()) throw EOFException("member $member is cut short")
                        inflater.setInput(buf, bufPos, bufLen - bufPos)
                        bufPos = bufLen
                    }
                }
            }
            return -1
        }

        private fun endMember() {
            // What the inflater did not use goes back to the buffer: the trailer starts there.
            bufPos = bufLen - inflater.remaining
            val crcValue = uint32()
            val size = uint32()
            if (crcValue != crc.value) throw ZipException("member $member: CRC-32 of the data does not match its trailer")
            if (size != (inflater.bytesWritten and 0xffffffffL)) throw ZipException("member $member: length does not match its trailer")
            // Another member, padding or the end.
            while (true) {
                if (bufPos == bufLen && !fill()) {
                    done = true
                    return
                }
                if (buf[bufPos].toInt() != 0) break
                bufPos++
            }
            if ((buf[bufPos].toInt() and 0xff) != GZIP_MAGIC_1) {
                throw ZipException("member ${member + 1} (at byte ${consumed + bufPos}): not a gzip header; the data after member $member is damaged or not gzip")
            }
            startMember()
        }

        /** Reads the header of the next member (its start is at bufPos). */
        private fun startMember() {
            member++
            val at = consumed + bufPos
            val what = "member $member (at byte $at)"
            if (byte() != GZIP_MAGIC_1 || byte() != GZIP_MAGIC_2) throw ZipException("$what: not a gzip header")
            if (byte() != 8) throw ZipException("$what: not deflate-compressed")
            val flags = byte()
            repeat(6) { byte() } // modification time, extra flags, operating system
            if (flags and 4 != 0) repeat(byte() or (byte() shl 8)) { byte() }
            if (flags and 8 != 0) while (byte() != 0) Unit
            if (flags and 16 != 0) while (byte() != 0) Unit
            if (flags and 2 != 0) repeat(2) { byte() }
            inflater.reset()
            crc.reset()
            inflater.setInput(buf, bufPos, bufLen - bufPos)
            bufPos = bufLen
        }

        private fun uint32(): Long {
            var v = 0L
            for (k in 0 until 4) v = v or (byte().toLong() shl (8 * k))
            return v
        }

        private fun byte(): Int {
            if (bufPos == bufLen && !fill()) throw EOFException("member $member is cut short")
            return buf[bufPos++].toInt() and 0xff
        }

        /** Refills the buffer when it is used up; false at the end of the input. */
        private fun fill(): Boolean {
            if (bufPos < bufLen) return true
            consumed += bufLen
            bufLen = 0
            bufPos = 0
            while (true) {
                val n = input.read(buf, 0, buf.size)
                if (n < 0) return false
                if (n > 0) {
                    bufLen = n
                    return true
                }
            }
        }

        override fun close() {
            inflater.end()
            input.close()
        }
    }
}
