/*
 * The cross-check of a zip's two indexes before any entry is read: the central directory (what
 * java.util.zip.ZipFile reads) and the local header in front of each entry's data (what a
 * streaming reader such as ZipInputStream, or an unzip tool, reads). A zip in which they
 * disagree, or with two entries of one name, reads differently in different tools: it is
 * refused, naming the archive and the entry, instead of replaying one of its readings.
 */
package dev.motionfusion.core.io

import java.io.EOFException
import java.nio.ByteBuffer
import java.nio.ByteOrder
import java.nio.channels.FileChannel
import java.nio.charset.StandardCharsets
import java.nio.file.Path
import java.nio.file.StandardOpenOption

internal object ZipDirectory {
    private const val EOCD_SIG = 0x06054b50
    private const val ZIP64_LOCATOR_SIG = 0x07064b50
    private const val ZIP64_EOCD_SIG = 0x06064b50
    private const val CEN_SIG = 0x02014b50
    private const val LOC_SIG = 0x04034b50
    private const val EOCD_BYTES = 22
    private const val CEN_BYTES = 46
    private const val LOC_BYTES = 30
    private const val MAX_COMMENT = 0xffff
    private const val U32 = 0xffffffffL
    private const val FLAG_DESCRIPTOR = 8

    /** One entry as the central directory describes it. */
    private class Entry(
        val name: String, val rawName: ByteArray, val flags: Int, val method: Int, val crc: Long,
        val compressed: Long, val size: Long, val offset: Long,
    )

    /**
     * Checks [file] (named [shown] in messages, its entries as "shown!/entry"): entry names are
     * unique; each local header matches its central directory entry in name, compression method,
     * and (when the local header carries them) CRC-32 and sizes; the entries follow each other
     * from the start of the file to the central directory with nothing between them (a gap could
     * hold an entry only a streaming reader sees).
     * @throws DataFormatException naming the archive (and the entry) on any disagreement.
     */
    fun verify(file: Path, shown: String) {
        try {
            FileChannel.open(file, StandardOpenOption.READ).use { ch -> verify(ch, shown) }
        } catch (e: EOFException) {
            throw DataFormatException(shown, 0, 0, "not a readable zip file: an entry or the central directory lies beyond the end of the file", e)
        } catch (e: IllegalArgumentException) {
            throw DataFormatException(shown, 0, 0, "not a readable zip file: an offset lies outside the file", e)
        }
    }

    private fun verify(ch: FileChannel, shown: String) {
        run {
            val (entries, cdStart) = central(ch, shown)
            val seen = HashSet<String>()
            for (e in entries) {
                if (!seen.add(e.name)) throw DataFormatException("$shown!/${e.name}", 0, 0, "the zip holds two entries of this name: which one is meant is ambiguous; not read")
            }
            var expected = 0L
            var descriptor = false
            for (e in entries.sortedBy { it.offset }) {
                val end = local(ch, e, shown)
                if (e.offset != expected && !(descriptor && isDescriptorGap(e.offset - expected))) {
                    throw DataFormatException(shown, 0, 0, "bytes $expected to ${e.offset} lie in no entry of the central directory (an entry only some tools see?); not read")
                }
                expected = end
                descriptor = e.flags and FLAG_DESCRIPTOR != 0
            }
            if (entries.isNotEmpty() && cdStart != expected && !(descriptor && isDescriptorGap(cdStart - expected))) {
                throw DataFormatException(shown, 0, 0, "bytes $expected to $cdStart lie in no entry of the central directory (an entry only some tools see?); not read")
            }
        }
    }

    /** A data descriptor (CRC-32 and sizes, with or without its signature, 32- or 64-bit sizes) after an entry's data. */
    private fun isDescriptorGap(gap: Long) = gap == 12L || gap == 16L || gap == 20L || gap == 24L

    /** The entries of the central directory and where it starts. */
    private fun central(ch: FileChannel, shown: String): Pair<List<Entry>, Long> {
        val size = ch.size()
        val tailLen = minOf(size, (EOCD_BYTES + MAX_COMMENT).toLong()).toInt()
        val tail = read(ch, size - tailLen, tailLen)
        var at = -1
        for (k in tailLen - EOCD_BYTES downTo 0) if (tail.getInt(k) == EOCD_SIG) { at = k; break }
        if (at < 0) throw DataFormatException(shown, 0, 0, "not a readable zip file: no end of central directory")
        var count = tail.getShort(at + 10).toLong() and 0xffff
        var cdSize = tail.getInt(at + 12).toLong() and U32
        var cdOffset = tail.getInt(at + 16).toLong() and U32
        val eocdPos = size - tailLen + at
        if ((count == 0xffffL || cdSize == U32 || cdOffset == U32) && eocdPos >= 20) {
            val loc = read(ch, eocdPos - 20, 20)
            if (loc.getInt(0) == ZIP64_LOCATOR_SIG) {
                val z = read(ch, loc.getLong(8), 56)
                if (z.getInt(0) != ZIP64_EOCD_SIG) throw DataFormatException(shown, 0, 0, "not a readable zip file: broken zip64 end of central directory")
                count = z.getLong(32)
                cdSize = z.getLong(40)
                cdOffset = z.getLong(48)
            }
        }
        if (cdOffset + cdSize > size || cdSize > Int.MAX_VALUE) throw DataFormatException(shown, 0, 0, "not a readable zip file: central directory outside the file")
        val cd = read(ch, cdOffset, cdSize.toInt())
        val out = ArrayList<Entry>()
        var p = 0
        while (p + CEN_BYTES <= cd.limit() && cd.getInt(p) == CEN_SIG) {
            val flags = cd.getShort(p + 8).toInt() and 0xffff
            val method = cd.getShort(p + 10).toInt() and 0xffff
            val crc = cd.getInt(p + 16).toLong() and U32
            var compressed = cd.getInt(p + 20).toLong() and U32
            var uncompressed = cd.getInt(p + 24).toLong() and U32
            val nameLen = cd.getShort(p + 28).toInt() and 0xffff
            val extraLen = cd.getShort(p + 30).toInt() and 0xffff
            val commentLen = cd.getShort(p + 32).toInt() and 0xffff
            var offset = cd.getInt(p + 42).toLong() and U32
            if (p + CEN_BYTES + nameLen + extraLen + commentLen > cd.limit()) break
            val raw = bytes(cd, p + CEN_BYTES, nameLen)
            // ZIP64 extended information: the 64-bit values of the fields that hold 0xffffffff.
            forExtra(cd, p + CEN_BYTES + nameLen, extraLen, 1) { x, len ->
                var q = x
                if (uncompressed == U32 && q + 8 <= x + len) { uncompressed = cd.getLong(q); q += 8 }
                if (compressed == U32 && q + 8 <= x + len) { compressed = cd.getLong(q); q += 8 }
                if (offset == U32 && q + 8 <= x + len) { offset = cd.getLong(q) }
            }
            out += Entry(String(raw, StandardCharsets.UTF_8), raw, flags, method, crc, compressed, uncompressed, offset)
            p += CEN_BYTES + nameLen + extraLen + commentLen
        }
        if (out.size.toLong() != count) throw DataFormatException(shown, 0, 0, "not a readable zip file: the central directory holds ${out.size} entries, its end says $count")
        return out to cdOffset
    }

    /** Checks the local header of [e] against it; returns where its data ends. */
    private fun local(ch: FileChannel, e: Entry, shown: String): Long {
        val entry = "$shown!/${e.name}"
        fun differs(what: String): Nothing =
            throw DataFormatException(entry, 0, 0, "its local header and the zip's central directory disagree ($what): the zip reads differently in different tools; not read")
        if (e.offset + LOC_BYTES > ch.size()) differs("the local header lies outside the file")
        val h = read(ch, e.offset, LOC_BYTES)
        if (h.getInt(0) != LOC_SIG) differs("no local header where the central directory points")
        val flags = h.getShort(6).toInt() and 0xffff
        val method = h.getShort(8).toInt() and 0xffff
        val crc = h.getInt(14).toLong() and U32
        var compressed = h.getInt(18).toLong() and U32
        var size = h.getInt(22).toLong() and U32
        val nameLen = h.getShort(26).toInt() and 0xffff
        val extraLen = h.getShort(28).toInt() and 0xffff
        val rest = read(ch, e.offset + LOC_BYTES, nameLen + extraLen)
        val raw = bytes(rest, 0, nameLen)
        if (!raw.contentEquals(e.rawName)) differs("name '${String(raw, StandardCharsets.UTF_8)}'")
        if (method != e.method) differs("compression method ${e.method} or $method")
        if (flags and FLAG_DESCRIPTOR == 0) {
            forExtra(rest, nameLen, extraLen, 1) { x, len ->
                var q = x
                if (size == U32 && q + 8 <= x + len) { size = rest.getLong(q); q += 8 }
                if (compressed == U32 && q + 8 <= x + len) { compressed = rest.getLong(q) }
            }
            if (crc != e.crc) differs("CRC-32 %08x or %08x".format(e.crc, crc))
            if (compressed != e.compressed) differs("compressed size ${e.compressed} or $compressed bytes")
            if (size != e.size) differs("size ${e.size} or $size bytes")
        }
        return e.offset + LOC_BYTES + nameLen + extraLen + e.compressed
    }

    /** Calls [block] with the start and length of the extra field [id] within [len] bytes at [at] of [b]. */
    private inline fun forExtra(b: ByteBuffer, at: Int, len: Int, id: Int, block: (Int, Int) -> Unit) {
        var q = at
        while (q + 4 <= at + len) {
            val tag = b.getShort(q).toInt() and 0xffff
            val n = b.getShort(q + 2).toInt() and 0xffff
            if (q + 4 + n > at + len) return
            if (tag == id) { block(q + 4, n); return }
            q += 4 + n
        }
    }

    private fun bytes(b: ByteBuffer, at: Int, n: Int) = ByteArray(n) { b.get(at + it) }

    private fun read(ch: FileChannel, at: Long, n: Int): ByteBuffer {
        val b = ByteBuffer.allocate(n).order(ByteOrder.LITTLE_ENDIAN)
        var pos = at
        while (b.hasRemaining()) {
            val r = ch.read(b, pos)
            if (r < 0) throw EOFException("zip ends early")
            pos += r
        }
        (b as java.nio.Buffer).flip() // Buffer.flip: ByteBuffer.flip does not exist before Java 9 (Android)
        return b
    }
}
