/*
 * Zip export and import of session folders: the zip holds one folder named after the session
 * with meta.json and the stream files (SessionReader also reads zips with the files at the root).
 */
package dev.motionfusion.core.session

import dev.motionfusion.core.io.AtomicFiles
import dev.motionfusion.core.io.DataFormatException
import dev.motionfusion.core.io.FileSet
import dev.motionfusion.core.io.InputLimits
import dev.motionfusion.core.io.ZipFolder
import java.io.OutputStream
import java.nio.file.Files
import java.nio.file.Path

public object SessionArchive {
    /**
     * Writes the session folder [dir] as a zip to [zipFile] (deflate), files inside a folder
     * named like [dir]. Only meta.json, the stream files and markers.csv are included. Entries carry the
     * files' modification times, or [entryTimeMs] when given (reproducible archives). The zip
     * is written aside and moved into place whole (AtomicFiles): a failure leaves [zipFile] as it was.
     */
    @JvmStatic
    @JvmOverloads
    public fun zip(dir: Path, zipFile: Path, entryTimeMs: Long? = null) {
        require(Files.isRegularFile(dir.resolve(SessionMetadata.FILE_NAME))) { "$dir is not a session folder (no meta.json)" }
        AtomicFiles().write(zipFile) { zip(dir, it, entryTimeMs) }
    }

    /**
     * As [zip], to a stream (e.g. a content:// URI's output stream on Android); does not close [out].
     * [progress], when given, is called with the bytes of the session's files read so far and their
     * total, after every 64 KiB and at the end; an exception it throws stops the zip there (a
     * cancelled export) and is thrown on.
     */
    @JvmStatic
    @JvmOverloads
    public fun zip(dir: Path, out: OutputStream, entryTimeMs: Long? = null, progress: ((Long, Long) -> Unit)? = null) {
        val folder = dir.toAbsolutePath().normalize().fileName?.toString() ?: "session"
        val files = SessionRecovery.SESSION_FILES.map { dir.resolve(it) }.filter { Files.isRegularFile(it) }
        ZipFolder.write(files.map { "$folder/${it.fileName}" to it }, out, entryTimeMs, progress)
    }

    /**
     * Extracts the session in [zipFile] into the new folder [target] (which must not exist).
     * Only flat files beside meta.json are extracted; paths are never followed out of [target].
     * Decompression is capped by [limits].
     * @throws DataFormatException when the zip is broken, holds no session or expands beyond the limits.
     */
    @JvmStatic
    @JvmOverloads
    public fun unzip(zipFile: Path, target: Path, limits: InputLimits = InputLimits()): Path {
        require(!Files.exists(target)) { "$target already exists" }
        FileSet.open(zipFile, limits).use { files ->
            val meta = files.paths.firstOrNull { it == SessionMetadata.FILE_NAME || it.endsWith("/" + SessionMetadata.FILE_NAME) }
            if (files.isFolder || meta == null) throw DataFormatException(zipFile.toString(), 0, 0, "no meta.json: not a session zip")
            val prefix = meta.removeSuffix(SessionMetadata.FILE_NAME)
            Files.createDirectories(target)
            for (path in files.filesIn(prefix)) {
                val name = path.removePrefix(prefix)
                if (name.isEmpty() || '\\' in name || name == "." || name == "..") continue
                val out = target.resolve(name).normalize()
                check(out.parent == target.normalize()) { "unsafe entry $path" }
                files.open(path, gunzip = false).use { input -> Files.newOutputStream(out).use { o -> input.copyTo(o, 1 shl 16) } }
            }
        }
        return target
    }
}
