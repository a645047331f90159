package dev.motionfusion.app.export

import java.io.File
import java.io.IOException
import java.io.OutputStream
import java.util.zip.ZipEntry
import java.util.zip.ZipOutputStream

/**
 * A session folder as one zip: every file of the folder under a top-level folder named after
 * the session (`<name>/…`), which is how `fusion replay` reads a zipped session. Files are
 * stored in name order with deflate; the stream is finished but not closed.
 */
internal object SessionZip {
    fun fileName(dir: File): String = "${dir.name}.zip"

    @Throws(IOException::class)
    fun write(dir: File, out: OutputStream) {
        if (!dir.isDirectory) throw IOException("no session ${dir.name}")
        val zip = ZipOutputStream(out)
        val files = dir.walkTopDown().filter { it.isFile }.sortedBy { it.relativeTo(dir).invariantSeparatorsPath }.toList()
        for (f in files) {
            val entry = ZipEntry("${dir.name}/${f.relativeTo(dir).invariantSeparatorsPath}")
            entry.time = f.lastModified()
            zip.putNextEntry(entry)
            f.inputStream().use { it.copyTo(zip, 64 * 1024) }
            zip.closeEntry()
        }
        zip.finish()
        zip.flush()
    }

    /** Writes the zip to [target] through a temporary file, so a failed export leaves no partial zip. */
    @Throws(IOException::class)
    fun writeTo(dir: File, target: File) {
        target.parentFile?.mkdirs()
        val tmp = File(target.parentFile, target.name + ".part")
        try {
            tmp.outputStream().use { write(dir, it) }
            if (target.exists()) target.delete()
            if (!tmp.renameTo(target)) throw IOException("cannot write ${target.name}")
        } finally {
            tmp.delete()
        }
    }
}
