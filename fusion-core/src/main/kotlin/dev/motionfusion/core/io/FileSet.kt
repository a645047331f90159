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

    protected abstract fun openRaw(path: String): InputStream

    /** How [path] is named in messages. */
    abstract fun displayName(path: String): String

    /** [path] decompressed (zip entry, and gzip unless not [gunzip]) and guarded. */
    fun open(path: String, gunzip: Boolean = true): InputStream =
        if (gunzip) Inputs.maybeGunzip(openRaw(path), displayName(path), guard) else openRaw(path)

    /** A CSV reader of [path]. */
    fun csv(path: String, separator: Byte = COMMA, decimalComma: Boolean = false, maxLineBytes: Int = ByteCsvReader.MAX_LINE_BYTES): ByteCsvReader =
        ByteCsvReader(open(path), displayName(path), separator, decimalComma, maxLineBytes)

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
        // decompressed at all is the answer the user needs, not "not a recognised input".
        if (e.cause is java.util.zip.ZipException || e.cause is java.io.EOFException) throw e
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
        override val paths: List<String> = list()

        private fun list(): List<String> {
            val root = dir.toRealPath()
            val found = ArrayList<String>()
            Files.walk(dir, MAX_DEPTH).use { s ->
                for (p in s) {
                    if (!Files.isRegularFile(p)) continue
                    val rel = dir.relativize(p).toString().replace('\\', '/')
                    if (rel.split('/').any { it.startsWith(".") || it == "__MACOSX" }) continue
                    // A link pointing out of the folder is not part of the recording.
                    if (!p.toRealPath().startsWith(root)) continue
                    found += rel
                    if (found.size > MAX_FILES) throw DataFormatException(dir.toString(), 0, 0, "more than $MAX_FILES files: name the recording's own folder")
                }
            }
            return found.sortedWith(compareBy<String>({ it.count { c -> c == '/' } }, { it }))
        }

        override fun openRaw(path: String): InputStream = Files.newInputStream(dir.resolve(path))
        override fun displayName(path: String) = dir.resolve(path).toString()
        override fun close() {}
    }

    private class Zip(private val file: Path, guard: CompressionGuard) : FileSet(guard) {
        private val zip = try {
            ZipFile(file.toFile())
        } catch (e: ZipException) {
            throw DataFormatException(file.toString(), 0, 0, "not a readable zip file: ${e.message}", e)
        } catch (e: IOException) {
            if (Files.isRegularFile(file)) throw DataFormatException(file.toString(), 0, 0, "not a readable zip file: ${e.message}", e)
            throw e
        }
        override val name: String = file.toString()
        override val paths: List<String> = try {
            zip.entries().asSequence().filter { !it.isDirectory }.map { it.name }
                .filter { n -> n.split('/').none { it.startsWith(".") || it == "__MACOSX" || it == ".." } }
                .take(MAX_FILES + 1).toList().also {
                    if (it.size > MAX_FILES) throw DataFormatException(file.toString(), 0, 0, "more than $MAX_FILES files in the zip")
                }
                .sortedWith(compareBy<String>({ it.count { c -> c == '/' } }, { it }))
        } catch (e: Throwable) {
            zip.close()
            if (e is IllegalArgumentException) throw DataFormatException(file.toString(), 0, 0, "not a readable zip file: ${e.message}", e)
            throw e
        }

        override fun openRaw(path: String): InputStream {
            val entry = zip.getEntry(path) ?: throw NoSuchFileException(displayName(path))
            return guard.wrap({ zip.getInputStream(entry) }, displayName(path))
        }

        override fun displayName(path: String) = "$file!/$path"
        override fun close() = zip.close()
    }

    /** One file seen as a set of one. */
    private class Single(private val file: Path, guard: CompressionGuard) : FileSet(guard) {
        override val name: String = file.toString()
        override val paths: List<String> = listOf(file.fileName.toString())
        override fun openRaw(path: String): InputStream = Files.newInputStream(file)
        override fun displayName(path: String) = file.toString()
        override fun close() {}
    }

    companion object {
        private const val COMMA = ','.code.toByte()
        const val MAX_DEPTH = 5
        const val MAX_FILES = 10_000
        const val SNIFF_BYTES = 1 shl 16

        /** A folder, a zip, or any other file as a set of one. */
        fun open(path: Path, limits: InputLimits = InputLimits()): FileSet {
            val guard = CompressionGuard(limits)
            return when {
                Files.isDirectory(path) -> Folder(path, guard)
                !Files.isRegularFile(path) -> throw NoSuchFileException(path.toString())
                isZip(path) -> Zip(path, guard)
                else -> Single(path, guard)
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
