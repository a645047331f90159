/*
 * The one folder-or-zip of every input format: a set of files by relative path ('/'-separated),
 * each opened through the compression guard (zip entries, and .gz files by their magic bytes).
 * Sessions, trials, phyphox and Sensor Logger exports are all read through it.
 */
package dev.motionfusion.core.io

import java.io.Closeable
import java.io.IOException
import java.io.InputStream
import java.nio.file.Files
import java.nio.file.NoSuchFileException
import java.nio.file.Path
import java.util.zip.ZipException
import java.util.zip.ZipFile

internal abstract class FileSet(val guard: CompressionGuard) : Closeable {
    /** The input as the user named it. */
    abstract val name: String

    /** True for a folder (which may hold zips of other recordings). */
    open val isFolder: Boolean get() = false

    /** Relative paths of the regular files, shallowest first. */
    abstract val paths: List<String>

    /** Relative paths of the links that point out of the folder: not part of the recording, not read. */
    open val linksOut: List<String> get() = emptyList()

    protected abstract fun openRaw(path: String): InputStream

    /** How [path] is named in messages. */
    abstract fun displayName(path: String): String

    /** [path] decompressed (zip entry, and gzip unless not [gunzip]) and guarded. */
    fun open(path: String, gunzip: Boolean = true): InputStream =
        if (gunzip) Inputs.maybeGunzip(openRaw(path), displayName(path), guard) else openRaw(path)

    /** A CSV reader of [path]. */
    fun csv(path: String, separator: Byte = COMMA, decimalComma: Boolean = false, maxLineBytes: Int = ByteCsvReader.MAX_LINE_BYTES): ByteCsvReader =
        open(path).let { s -> ByteCsvReader(s, displayName(path), separator, decimalComma, maxLineBytes, compressed = this is Zip || s is Decompressed) }

    /** The file named [baseName] (case-insensitive) directly in [dir] ("" for the root, else ending in '/'), or null. */
    fun find(dir: String, baseName: String): String? =
        paths.firstOrNull { it.length == dir.length + baseName.length && it.startsWith(dir) && it.regionMatches(dir.length, baseName, 0, baseName.length, ignoreCase = true) }

    /** Files directly in [dir]. */
    fun filesIn(dir: String): List<String> = paths.filter { it.startsWith(dir) && it.indexOf('/', dir.length) < 0 }

    /**
     * The first line of [path] (at most [maxBytes]), or null when it is empty, unreadable or its
     * first line is longer. Sniffing does not count toward the total of a reading ([CompressionGuard.reset]).
     */
    fun firstLine(path: String, maxBytes: Int = SNIFF_BYTES): String? = try {
        guard.reset()
        csv(path, maxLineBytes = maxBytes).use { if (it.nextLine()) it.lineText() else null }
    } catch (e: DataFormatException) {
        // A line that does not fit the sniffing bound is "not this kind"; data that cannot be
        // decompressed at all, or only beyond the limits, is the answer the user needs, not "not a recognised input".
        if (e.cause is java.util.zip.ZipException || e.cause is java.io.EOFException || e.cause is OverLimit) throw e
        null
    }

    /** The whole of the small file [path]; a file longer than [maxBytes] is an error (never read into memory whole). */
    fun readSmall(path: String, maxBytes: Int): ByteArray = open(path).use { s ->
        val out = java.io.ByteArrayOutputStream()
        val buf = ByteArray(8192)
        while (true) {
            val n = s.read(buf)
            if (n < 0) break
            out.write(buf, 0, n)
            if (out.size() > maxBytes) throw DataFormatException(displayName(path), 0, 0, "larger than $maxBytes bytes: not what this file should hold")
        }
        out.toByteArray()
    }

    private class Folder(private val dir: Path, guard: CompressionGuard) : FileSet(guard) {
        override val name: String = dir.toString()
        override val isFolder: Boolean get() = true
        override val linksOut = ArrayList<String>()
        override val paths: List<String> = list()

        private fun list(): List<String> {
            // From the folder's real path: the folder given may itself be a link to one (walked, its links not followed).
            val root = dir.toRealPath()
            val found = ArrayList<String>()
            Files.walk(root, MAX_DEPTH).use { s ->
                for (p in s) {
                    val rel = root.relativize(p).toString().replace('\\', '/')
                    if (hidden(rel)) continue
                    if (!Files.isRegularFile(p)) {
                        // A link to a folder elsewhere is named, as a link to a file is: what it holds is not read.
                        if (Files.isSymbolicLink(p) && Files.isDirectory(p) && !p.toRealPath().startsWith(root)) linksOut += rel
                        continue
                    }
                    // A link pointing out of the folder is not part of the recording.
                    if (!p.toRealPath().startsWith(root)) {
                        linksOut += rel
                        continue
                    }
                    found += rel
                    if (found.size > MAX_FILES) throw DataFormatException(dir.toString(), 0, 0, "more than $MAX_FILES files: name the recording's own folder")
                }
            }
            return found.sortedWith(compareBy<String>({ it.count { c -> c == '/' } }, { it }))
        }

        private fun hidden(rel: String) = rel.split('/').any { it.startsWith(".") || it == "__MACOSX" }

        override fun openRaw(path: String): InputStream = Files.newInputStream(dir.resolve(path))
        override fun displayName(path: String) = dir.resolve(path).toString()
        override fun close() {}
    }

    /**
     * A zip file (named [shown]); its central directory is checked against its local headers
     * first ([ZipDirectory]), and each entry read to its end against its CRC-32 and size.
     */
    private class Zip(private val file: Path, guard: CompressionGuard, private val shown: String, private val spool: Path?) : FileSet(guard) {
        private val zip = try {
            ZipDirectory.verify(file, shown)
            ZipFile(file.toFile())
        } catch (e: ZipException) {
            throw DataFormatException(shown, 0, 0, "not a readable zip file: ${e.message}", e)
        } catch (e: IOException) {
            if (Files.isRegularFile(file)) throw DataFormatException(shown, 0, 0, "not a readable zip file: ${e.message}", e)
            throw e
        }
        override val name: String = shown
        override val paths: List<String> = try {
            zip.entries().asSequence().filter { !it.isDirectory }.map { it.name }
                .filter { n -> n.split('/').none { it.startsWith(".") || it == "__MACOSX" || it == ".." } }
                .take(MAX_FILES + 1).toList().also {
                    if (it.size > MAX_FILES) throw DataFormatException(shown, 0, 0, "more than $MAX_FILES files in the zip")
                }
                .sortedWith(compareBy<String>({ it.count { c -> c == '/' } }, { it }))
        } catch (e: Throwable) {
            zip.close()
            if (e is IllegalArgumentException) throw DataFormatException(shown, 0, 0, "not a readable zip file: ${e.message}", e)
            throw e
        }

        override fun openRaw(path: String): InputStream {
            val entry = zip.getEntry(path) ?: throw NoSuchFileException(displayName(path))
            return guard.wrap({ CheckedEntry(zip.getInputStream(entry), entry.crc, entry.size) }, displayName(path))
        }

        override fun displayName(path: String) = "$shown!/$path"
        override fun close() {
            zip.close()
            spool?.let { Files.deleteIfExists(it); TemporaryFiles.remove(it) }
        }
    }

    /** A zip entry's data, checked at its end against the [crc] and [size] of the central directory. */
    private class CheckedEntry(inner: InputStream, private val crc: Long, private val size: Long) : java.io.FilterInputStream(inner) {
        private val sum = java.util.zip.CRC32()
        private var count = 0L

        override fun read(): Int {
            val b = super.read()
            if (b < 0) atEnd() else { sum.update(b); count++ }
            return b
        }

        override fun read(b: ByteArray, off: Int, len: Int): Int {
            val n = super.read(b, off, len)
            if (n < 0) atEnd() else if (n > 0) { sum.update(b, off, n); count += n }
            return n
        }

        override fun skip(n: Long): Long {
            val buf = ByteArray(8192)
            var left = n
            while (left > 0) {
                val r = read(buf, 0, minOf(left, buf.size.toLong()).toInt())
                if (r < 0) break
                left -= r
            }
            return n - left
        }

        private fun atEnd() {
            if (size >= 0 && count != size) throw ZipException("holds $count bytes, the zip's central directory says $size")
            if (crc >= 0 && sum.value != crc) throw ZipException("CRC-32 %08x of the data differs from the %08x of the zip's central directory".format(sum.value, crc))
        }
    }

    /** One file seen as a set of one, named [shown]; [spool] is deleted on close. */
    private class Single(private val file: Path, guard: CompressionGuard, private val shown: String, private val spool: Path?) : FileSet(guard) {
        override val name: String = shown
        override val paths: List<String> = listOf(if (spool != null) shown else file.fileName.toString())
        override fun openRaw(path: String): InputStream = Files.newInputStream(file)
        override fun displayName(path: String) = shown
        override fun close() {
            spool?.let { Files.deleteIfExists(it); TemporaryFiles.remove(it) }
        }
    }

    companion object {
        private const val COMMA = ','.code.toByte()
        const val MAX_DEPTH = 5
        const val MAX_FILES = 10_000
        const val SNIFF_BYTES = 1 shl 16

        private const val EMPTY = "empty: nothing was read from it (an empty input holds no recording)"

        /**
         * A folder, a zip, or any other file as a set of one. Standard input ("-"), a pipe, a
         * FIFO or a device is read once into a temporary file (deleted on close; at most the
         * total limit of [limits]) and then read as the file it holds (zip, gzip or plain).
         * @throws NoSuchFileException when [path] does not exist; a FileSystemException naming it when it cannot be read.
         * @throws DataFormatException when such a stream is empty (e.g. /dev/null).
         */
        fun open(path: Path, limits: InputLimits = InputLimits()): FileSet {
            val guard = CompressionGuard(limits)
            val shown = Inputs.shown(path)
            if (Inputs.isStandardInput(path)) return spooled(System.`in`, shown, guard)
            // Read once, links followed: missing, too long a path, no permission are named here.
            val kind = try {
                Files.readAttributes(path, java.nio.file.attribute.BasicFileAttributes::class.java)
            } catch (e: NoSuchFileException) {
                throw NoSuchFileException(shown)
            } catch (e: IOException) {
                throw java.nio.file.FileSystemException(shown, null, AtomicFiles.reason(e)).apply { initCause(e) }
            }
            return when {
                kind.isDirectory -> Folder(path, guard)
                kind.isRegularFile && kind.size() == 0L -> throw DataFormatException(shown, 0, 0, EMPTY)
                kind.isRegularFile -> if (isZip(path)) Zip(path, guard, shown, null) else Single(path, guard, shown, null)
                else -> AtomicFiles.named(path) { Files.newInputStream(path) }.use { spooled(it, shown, guard) }
            }
        }

        private fun spooled(input: InputStream, shown: String, guard: CompressionGuard): FileSet {
            val spool = TemporaryFiles.createInput()
            try {
                // Opened without CREATE: if a signal's clean-up has removed it, it is not made again.
                val size = Files.newOutputStream(spool, java.nio.file.StandardOpenOption.WRITE).use { out ->
                    val buf = ByteArray(Inputs.BUFFER_BYTES)
                    var total = 0L
                    while (true) {
                        val n = try {
                            input.read(buf)
                        } catch (e: IOException) {
                            throw java.nio.file.FileSystemException(shown, null, AtomicFiles.reason(e)).apply { initCause(e) }
                        }
                        if (n < 0) break
                        total += n
                        if (total > guard.limits.maxTotalBytes) {
                            throw DataFormatException(shown, 0, 0, "more than ${guard.limits.maxTotalBytes} bytes (raise the limit with --max-uncompressed)")
                        }
                        try {
                            out.write(buf, 0, n)
                        } catch (e: IOException) {
                            throw java.nio.file.FileSystemException(spool.toAbsolutePath().parent.toString(), null,
                                "$shown is read once into a temporary file here (java.io.tmpdir; give it room, or another folder with -Djava.io.tmpdir=DIR): ${AtomicFiles.reason(e)}").apply { initCause(e) }
                        }
                    }
                    total
                }
                if (size == 0L) throw DataFormatException(shown, 0, 0, EMPTY)
                return if (isZip(spool)) Zip(spool, guard, shown, spool) else Single(spool, guard, shown, spool)
            } catch (e: Throwable) {
                Files.deleteIfExists(spool)
                TemporaryFiles.remove(spool)
                throw e
            }
        }

        private fun isZip(path: Path): Boolean = Files.newInputStream(path).use { s ->
            val b = ByteArray(4)
            var n = 0
            while (n < 4) {
                val r = s.read(b, n, 4 - n)
                if (r < 0) break
                n += r
            }
            n == 4 && b[0] == 'P'.code.toByte() && b[1] == 'K'.code.toByte() && b[2].toInt() == 3 && b[3].toInt() == 4
        }
    }
}
