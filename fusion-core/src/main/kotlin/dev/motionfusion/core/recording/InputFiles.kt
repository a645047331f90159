/*
 * A folder or a zip seen as a set of files found by their base name (exports put their CSVs at
 * the zip's root or in one folder).
 */
package dev.motionfusion.core.recording

import dev.motionfusion.core.io.DataFormatException
import java.io.Closeable
import java.io.InputStream
import java.nio.file.Files
import java.nio.file.NoSuchFileException
import java.nio.file.Path
import java.util.stream.Collectors
import java.util.zip.ZipException
import java.util.zip.ZipFile

internal abstract class InputFiles : Closeable {
    abstract val name: String

    /** Relative paths of all regular files. */
    abstract val paths: List<String>
    abstract fun open(path: String): InputStream
    abstract fun displayName(path: String): String

    /** The shallowest file whose base name is [baseName] (case-insensitive), or null. */
    fun find(baseName: String): String? =
        paths.filter { it.substringAfterLast('/').equals(baseName, ignoreCase = true) }.minByOrNull { it.count { c -> c == '/' } }

    /** The first line of [path] (BOM removed), or null when empty. */
    fun firstLine(path: String): String? = open(path).use { s ->
        dev.motionfusion.core.io.Inputs.reader(s).readLine()?.removePrefix("\uFEFF")
    }

    private class Folder(private val dir: Path) : InputFiles() {
        override val name = dir.fileName?.toString() ?: dir.toString()
        override val paths: List<String> = Files.walk(dir, 2).use { s ->
            s.filter { Files.isRegularFile(it) }.map { dir.relativize(it).toString().replace('\\', '/') }.collect(Collectors.toList())
        }
        override fun open(path: String): InputStream = Files.newInputStream(dir.resolve(path))
        override fun displayName(path: String) = dir.resolve(path).toString()
        override fun close() {}
    }

    private class Zip(private val file: Path) : InputFiles() {
        private val zip = try {
            ZipFile(file.toFile())
        } catch (e: ZipException) {
            throw DataFormatException(file.toString(), 0, 0, "not a readable zip file: ${e.message}", e)
        }
        override val name = file.fileName.toString()
        override val paths: List<String> = zip.entries().asSequence().filter { !it.isDirectory }.map { it.name }.toList()
        override fun open(path: String): InputStream = zip.getEntry(path)?.let { zip.getInputStream(it) } ?: throw NoSuchFileException(displayName(path))
        override fun displayName(path: String) = "$file!/$path"
        override fun close() = zip.close()
    }

    companion object {
        fun open(path: Path): InputFiles = when {
            Files.isDirectory(path) -> Folder(path)
            Files.isRegularFile(path) -> Zip(path)
            else -> throw NoSuchFileException(path.toString())
        }
    }
}
