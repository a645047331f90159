/*
 * Durable, all-or-nothing file writing, the one mechanism every writer of the project uses
 * (session metadata, recovery, the app's rename, every output of the `fusion` command):
 * the bytes go to a new temporary file in the target's folder, are synced to the device, and
 * the file is renamed over the target (an atomic step on one file system), then the folder is
 * synced so the rename itself survives power loss. A reader sees the old file or the new one,
 * never a part; a failed or killed write leaves the target as it was.
 *
 * The file-system steps go through FileOperations, passed by constructor, so tests can make
 * storage fail after N bytes or "kill" the process at any step.
 */
package dev.motionfusion.core.io

import java.io.IOException
import java.io.OutputStream
import java.nio.ByteBuffer
import java.nio.channels.FileChannel
import java.nio.file.FileAlreadyExistsException
import java.nio.file.FileSystemException
import java.nio.file.Files
import java.nio.file.LinkOption
import java.nio.file.Path
import java.nio.file.StandardCopyOption
import java.nio.file.StandardOpenOption
import java.util.Random

/** A file open for writing that can be forced to the storage device. */
public abstract class SyncedOutput : OutputStream() {
    /** Forces every byte written so far to the storage device (fsync). */
    public abstract fun sync()
}

/**
 * The file-system steps of durable writing. [SYSTEM] is the real file system; tests pass an
 * implementation that fails or stops at a chosen step. [create], [truncate] and [delete]
 * never act through a symbolic link at the path they are given; [open] opens what is there
 * (a pipe or a device too).
 */
public interface FileOperations {
    /** Creates the new file [path] for writing; fails when anything (a file, a link) is there. */
    public fun create(path: Path): SyncedOutput

    /**
     * Opens [path] for writing from its start: created when missing, an existing file cut to
     * nothing (the stream files of a new session folder).
     */
    public fun open(path: Path): SyncedOutput

    /** Cuts the existing regular file [path] to [size] bytes and syncs it (never through a link). */
    public fun truncate(path: Path, size: Long)

    /** Renames [source] to [target] in one atomic step, replacing a file at [target] when [replace]. */
    public fun move(source: Path, target: Path, replace: Boolean)

    /** Forces the entries of the folder [dir] (new names, renames) to the storage device. */
    public fun syncFolder(dir: Path)

    /** Removes [path] if it exists (a link is removed, not its target). */
    public fun delete(path: Path)

    public companion object {
        /** The real file system. */
        @JvmField
        public val SYSTEM: FileOperations = SystemFileOperations
    }
}

/**
 * Writes files all-or-nothing through [ops] (see the file comment). Failures are
 * [FileSystemException]s that name the file and the reason.
 */
public class AtomicFiles(private val ops: FileOperations = FileOperations.SYSTEM) {

    /** Replaces (or creates) [target] with [bytes]. */
    public fun write(target: Path, bytes: ByteArray): Unit = write(target) { it.write(bytes) }

    /** Replaces (or creates) [target] with what [content] writes; on any failure [target] is untouched. */
    public fun write(target: Path, content: (OutputStream) -> Unit) {
        val out = open(target)
        try {
            content(out)
            out.commit()
        } finally {
            out.abort()
        }
    }

    /**
     * Starts writing [target] aside: write to the returned stream, then [PendingFile.commit] to
     * move it into place, or [PendingFile.abort] (also after commit: then it does nothing).
     * Closing the stream does neither (wrappers such as a GZIPOutputStream may close it).
     */
    public fun open(target: Path): PendingFile {
        val dir = target.toAbsolutePath().parent ?: throw FileSystemException(target.toString(), null, "has no folder")
        val name = target.fileName.toString()
        var attempt = 0
        while (true) {
            val tmp = dir.resolve(temporaryName(name, java.lang.Long.toHexString(random.nextLong() and 0xffffffffffL)))
            try {
                TemporaryFiles.add(tmp)
                return PendingFile(target.toAbsolutePath(), tmp, ops, ops.create(tmp))
            } catch (e: FileAlreadyExistsException) {
                TemporaryFiles.remove(tmp)
                if (++attempt >= 10) throw FileSystemException(target.toString(), null, "cannot create a temporary file beside it")
            } catch (e: IOException) {
                TemporaryFiles.remove(tmp)
                throw FileSystemException(target.toString(), null, reason(e)).apply { initCause(e) }
            } catch (e: Throwable) {
                TemporaryFiles.remove(tmp)
                throw e
            }
        }
    }

    /** Renames the file or folder [source] to the new name [target] (which must not exist) and syncs the folder. */
    public fun rename(source: Path, target: Path) {
        named(target) {
            ops.move(source, target, replace = false)
            ops.syncFolder(target.toAbsolutePath().parent)
        }
    }

    /**
     * A file being written aside of [target]. Bytes go straight to the temporary file (wrap in
     * a buffer); every failure names [target].
     */
    public class PendingFile internal constructor(
        /** Where the file goes on [commit]. */
        public val target: Path,
        private val tmp: Path,
        private val ops: FileOperations,
        private val sink: SyncedOutput,
    ) : OutputStream() {
        private var closed = false
        private var done = false

        override fun write(b: Int) {
            check()
            named(target) { sink.write(b) }
        }

        override fun write(b: ByteArray, off: Int, len: Int) {
            check()
            named(target) { sink.write(b, off, len) }
        }

        /** Marks the stream finished; the file stays aside until [commit]. */
        override fun close() {
            closed = true
        }

        /** Syncs the file, renames it over [target] and syncs the folder. */
        public fun commit() {
            if (done) throw IOException("$target: already committed or aborted")
            named(target) {
                sink.sync()
                sink.close()
                ops.move(tmp, target, replace = true)
                TemporaryFiles.remove(tmp)
                done = true
                ops.syncFolder(target.parent)
            }
        }

        /** Removes the temporary file unless [commit] succeeded; never throws. */
        public fun abort() {
            if (done) return
            done = true
            try {
                sink.close()
            } catch (e: IOException) {
                // The file is removed below anyway.
            }
            try {
                ops.delete(tmp)
                TemporaryFiles.remove(tmp)
            } catch (e: IOException) {
                // Nothing more can be done; the leftover has the temporary suffix (and stays listed for the shutdown hook).
            }
        }

        private fun check() {
            if (closed || done) throw IOException("$target: stream closed")
        }
    }

    public companion object {
        /** Suffix of the temporary files (".NAME.RANDOM.tmp" beside the target). */
        public const val TEMP_SUFFIX: String = ".tmp"

        private val random = Random()

        /**
         * The name of a temporary file or folder beside [targetName]: `.NAME.OWNER-HEX.tmp` (OWNER:
         * [TemporaryFiles.owner], e.g. the process id), or `.NAME.HEX.tmp` without an owner.
         */
        @JvmStatic
        public fun temporaryName(targetName: String, hex: String): String = ".$targetName.${TemporaryFiles.tag("-")}$hex$TEMP_SUFFIX"

        /**
         * Removes the temporary files and folders of writes aside of [target] left by a run that
         * was killed: those named as [temporaryName] makes them, last modified before [startedMs]
         * (this process's start), whose owner [alive] says is no longer running (a name without an
         * owner: by its age alone). Returns the names removed; never throws.
         */
        @JvmStatic
        public fun removeStale(target: Path, startedMs: Long, alive: (String) -> Boolean): List<String> {
            val dir = target.toAbsolutePath().parent ?: return emptyList()
            val name = target.fileName?.toString() ?: return emptyList()
            val removed = ArrayList<String>()
            runCatching {
                Files.newDirectoryStream(dir) { isTemporaryOf(it.fileName.toString(), name) }.use { s ->
                    for (p in s) {
                        val middle = p.fileName.toString().removePrefix(".$name.").removeSuffix(TEMP_SUFFIX)
                        val owner = middle.substringBefore('-', "")
                        if (owner.isNotEmpty() && alive(owner)) continue
                        val modified = runCatching { Files.getLastModifiedTime(p, java.nio.file.LinkOption.NOFOLLOW_LINKS).toMillis() }.getOrNull() ?: continue
                        if (modified >= startedMs) continue
                        TemporaryFiles.removeTree(p)
                        if (!Files.exists(p, java.nio.file.LinkOption.NOFOLLOW_LINKS)) removed += p.fileName.toString()
                    }
                }
            }
            return removed
        }

        /** True when [fileName] is a temporary file of a write aside of [targetName]. */
        @JvmStatic
        internal fun isTemporaryOf(fileName: String, targetName: String): Boolean =
            fileName.startsWith(".$targetName.") && fileName.endsWith(TEMP_SUFFIX)

        /** The reason of [e] in words, without the file name ("permission denied", "No space left on device"). */
        @JvmStatic
        public fun reason(e: IOException): String = when (e) {
            is java.nio.file.AccessDeniedException -> "permission denied"
            is java.nio.file.NoSuchFileException -> "no such file or folder"
            is FileAlreadyExistsException -> "already exists"
            is java.nio.file.DirectoryNotEmptyException -> "folder not empty"
            is java.nio.file.NotDirectoryException -> "not a folder"
            is FileSystemException -> plain(e.reason) ?: e.javaClass.simpleName
            else -> plain(e.message) ?: e.javaClass.simpleName
        }

        /** The system's reason, with ENAMETOOLONG ("File name too long") said in full. */
        private fun plain(reason: String?): String? =
            if (reason == "File name too long") "path too long: a name in it, or the whole path, is longer than the file system allows (on Linux 255 bytes a name, 4096 a path)" else reason

        /** Runs [block]; an IOException is re-thrown as a [FileSystemException] naming [file] and the reason. */
        public inline fun <T> named(file: Path, block: () -> T): T = try {
            block()
        } catch (e: IOException) {
            if (e is FileSystemException && e.file == file.toString() && e.reason != null) throw e
            throw FileSystemException(file.toString(), null, reason(e)).apply { initCause(e) }
        }
    }
}

/** [FileOperations] on the real file system (java.nio). */
private object SystemFileOperations : FileOperations {
    override fun create(path: Path): SyncedOutput =
        ChannelOutput(FileChannel.open(path, StandardOpenOption.CREATE_NEW, StandardOpenOption.WRITE))

    override fun open(path: Path): SyncedOutput =
        ChannelOutput(FileChannel.open(path, StandardOpenOption.CREATE, StandardOpenOption.TRUNCATE_EXISTING, StandardOpenOption.WRITE))

    override fun truncate(path: Path, size: Long) {
        FileChannel.open(path, StandardOpenOption.WRITE, LinkOption.NOFOLLOW_LINKS).use { ch ->
            ch.truncate(size)
            ch.force(true)
        }
    }

    override fun move(source: Path, target: Path, replace: Boolean) {
        if (replace) {
            Files.move(source, target, StandardCopyOption.ATOMIC_MOVE)
        } else {
            // ATOMIC_MOVE may replace an existing target: refuse one first (a race is left to rename(2)).
            if (Files.exists(target, LinkOption.NOFOLLOW_LINKS)) throw FileAlreadyExistsException(target.toString())
            Files.move(source, target)
        }
    }

    override fun syncFolder(dir: Path) {
        val ch = try {
            FileChannel.open(dir, StandardOpenOption.READ)
        } catch (e: IOException) {
            return // a platform that cannot open folders (Windows): its renames are synced by the file system
        }
        ch.use { it.force(true) }
    }

    override fun delete(path: Path) {
        Files.deleteIfExists(path)
    }
}

/** A [SyncedOutput] on a FileChannel. */
private class ChannelOutput(private val ch: FileChannel) : SyncedOutput() {
    override fun write(b: Int) = write(byteArrayOf(b.toByte()), 0, 1)

    override fun write(b: ByteArray, off: Int, len: Int) {
        val buf = ByteBuffer.wrap(b, off, len)
        while (buf.hasRemaining()) ch.write(buf)
    }

    override fun sync() = ch.force(true)

    override fun close() = ch.close()
}
