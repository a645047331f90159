/*
 * The temporary files and folders of this process: a file or session folder written aside
 * (AtomicFiles, the CLI's outputs), a spooled standard input, an offline spill that could not be
 * unlinked while open. Each is listed while it exists; a shutdown hook removes those still listed
 * when the process ends before it did (SIGTERM, Ctrl-C, System.exit). After a SIGKILL nothing
 * runs: the next run that writes the same output removes what is left (AtomicFiles.removeStale).
 */
package dev.motionfusion.core.io

import java.nio.file.Files
import java.nio.file.LinkOption
import java.nio.file.Path
import java.util.concurrent.ConcurrentHashMap

public object TemporaryFiles {
    private val paths = ConcurrentHashMap.newKeySet<Path>()

    /**
     * The owner's tag in temporary names (the CLI sets its process id, so that a later run can tell
     * a leftover of a process that is gone from the file of one still running); empty by default.
     */
    @Volatile
    public var owner: String = ""

    init {
        Runtime.getRuntime().addShutdownHook(Thread({ for (p in paths) removeTree(p) }, "temporary-files-cleanup"))
    }

    /** Lists [path] (a file or folder) to be removed if the process ends before [remove]. */
    @JvmStatic
    public fun add(path: Path) {
        paths.add(path)
    }

    /** Unlists [path] (removed, or moved into place). */
    @JvmStatic
    public fun remove(path: Path) {
        paths.remove(path)
    }

    /** Start of the name of a spooled standard input (or pipe) in the system's temporary folder: then the owner, '-', a number, `.tmp`. */
    public const val INPUT_PREFIX: String = "fusion-input-"

    /**
     * Removes the spooled inputs in the system's temporary folder (java.io.tmpdir) left by a run
     * that was killed: named with an owner that [alive] says is no longer running, last modified
     * before [startedMs]. Returns the paths removed; never throws.
     */
    @JvmStatic
    public fun removeStaleInputs(startedMs: Long, alive: (String) -> Boolean): List<String> {
        val removed = ArrayList<String>()
        runCatching {
            val dir = java.nio.file.Paths.get(System.getProperty("java.io.tmpdir"))
            Files.newDirectoryStream(dir) { val n = it.fileName.toString(); n.startsWith(INPUT_PREFIX) && n.endsWith(AtomicFiles.TEMP_SUFFIX) }.use { s ->
                for (p in s) {
                    val owner = p.fileName.toString().removePrefix(INPUT_PREFIX).substringBefore('-', "")
                    if (owner.isEmpty() || alive(owner)) continue
                    val modified = runCatching { Files.getLastModifiedTime(p, LinkOption.NOFOLLOW_LINKS).toMillis() }.getOrNull() ?: continue
                    if (modified >= startedMs || !Files.isRegularFile(p, LinkOption.NOFOLLOW_LINKS)) continue
                    if (runCatching { Files.deleteIfExists(p) }.getOrDefault(false)) removed += p.toString()
                }
            }
        }
        return removed
    }

    /**
     * A new empty file for a spooled input in the system's temporary folder, listed before it is
     * created (so a signal at any moment finds it listed): `fusion-input-OWNER-N.tmp`.
     */
    internal fun createInput(): Path {
        val dir = java.nio.file.Paths.get(System.getProperty("java.io.tmpdir"))
        while (true) {
            val p = dir.resolve(INPUT_PREFIX + tag("-") + java.lang.Long.toUnsignedString(random.nextLong()) + AtomicFiles.TEMP_SUFFIX)
            add(p)
            try {
                // Readable by its owner only, as Files.createTempFile makes it: a spooled input may be private.
                return if (dir.fileSystem.supportedFileAttributeViews().contains("posix")) {
                    Files.createFile(p, java.nio.file.attribute.PosixFilePermissions.asFileAttribute(java.nio.file.attribute.PosixFilePermissions.fromString("rw-------")))
                } else {
                    Files.createFile(p)
                }
            } catch (e: java.nio.file.FileAlreadyExistsException) {
                remove(p)
            } catch (e: Throwable) {
                remove(p)
                throw e
            }
        }
    }

    private val random = java.security.SecureRandom()

    /** The owner tag followed by [separator], or nothing without an owner. */
    internal fun tag(separator: String): String = owner.let { if (it.isEmpty()) "" else it + separator }

    /**
     * Removes [p], a file or a folder with what it holds (links removed, never followed); never
     * throws. The process's other threads keep running while shutdown hooks do, so a folder may
     * gain a file between its listing and its removal: it is listed again, a few times.
     */
    internal fun removeTree(p: Path) {
        for (attempt in 0 until 20) {
            val gone = runCatching {
                if (Files.isDirectory(p, LinkOption.NOFOLLOW_LINKS)) Files.newDirectoryStream(p).use { s -> s.toList() }.forEach { removeTree(it) }
                Files.deleteIfExists(p)
                true
            }.getOrDefault(false)
            if (gone || !Files.isDirectory(p, LinkOption.NOFOLLOW_LINKS)) return
        }
    }
}
