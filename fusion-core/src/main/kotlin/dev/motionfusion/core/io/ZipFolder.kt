package dev.motionfusion.core.io

import java.io.BufferedOutputStream
import java.io.OutputStream
import java.nio.file.Files
import java.nio.file.Path
import java.util.zip.ZipEntry
import java.util.zip.ZipOutputStream

/** Files written as a zip (deflate): the session archive and the zipped export folders. */
internal object ZipFolder {
    /**
     * Writes [entries] (name in the zip → file) to [out], which it finishes but does not close. Entries
     * carry the files' modification times, or [entryTimeMs] when given. [progress], when given, gets the
     * bytes read so far and their total after every 64 KiB and at the end; an exception it throws stops there.
     */
    fun write(entries: List<Pair<String, Path>>, out: OutputStream, entryTimeMs: Long? = null, progress: ((Long, Long) -> Unit)? = null) {
        val z = ZipOutputStream(BufferedOutputStream(out, 1 shl 16))
        val total = entries.sumOf { Files.size(it.second) }
        var done = 0L
        val buf = ByteArray(1 shl 16)
        progress?.invoke(0L, total)
        for ((name, f) in entries) {
            val e = ZipEntry(name)
            e.time = entryTimeMs ?: Files.getLastModifiedTime(f).toMillis()
            z.putNextEntry(e)
            Files.newInputStream(f).use { input ->
                while (true) {
                    val n = input.read(buf)
                    if (n < 0) break
                    z.write(buf, 0, n)
                    done += n
                    progress?.invoke(done, maxOf(total, done))
                }
            }
            z.closeEntry()
        }
        z.finish()
        z.flush()
    }

    /** Every file under [folder] (sorted by path), inside a folder [name] in the zip. */
    fun write(folder: Path, name: String, out: OutputStream) {
        val files = Files.walk(folder).use { s -> s.filter { Files.isRegularFile(it) }.sorted().collect(java.util.stream.Collectors.toList()) }
        write(files.map { "$name/" + folder.relativize(it).joinToString("/") to it }, out)
    }

    /** Removes [folder] and what it holds; never throws. */
    fun removeTree(folder: Path) = TemporaryFiles.removeTree(folder)
}
