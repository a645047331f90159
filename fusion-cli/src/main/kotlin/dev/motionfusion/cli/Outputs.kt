package dev.motionfusion.cli

import dev.motionfusion.core.io.AtomicFiles
import dev.motionfusion.core.io.FileOperations
import dev.motionfusion.core.io.TemporaryFiles
import java.io.IOException
import java.io.OutputStream
import java.io.PrintStream
import java.nio.file.FileSystemException
import java.nio.file.Files
import java.nio.file.LinkOption
import java.nio.file.Path
import java.nio.file.StandardOpenOption

/**
 * Every file a command writes goes through here (one per run of [Cli]):
 *  - an output that is an input, or lies inside an input folder, is refused (a
 *    [UsageException], exit 2) before anything is opened for writing; real paths are compared,
 *    so symbolic and hard links to an input are refused too; so is a second output of the run
 *    that names the same file as another (`-o` and `--rows`);
 *  - an output is written aside (a temporary file, or folder, beside it) and moved into place
 *    by [commit], which [Cli] calls only when the run succeeded and standard output took
 *    everything; otherwise [abort] removes what was written aside and the previous file stays
 *    as it was. An output that is a device or a pipe (e.g. /dev/null) is written directly.
 *  - temporary files and folders are listed with TemporaryFiles, whose shutdown hook removes
 *    them when the process is ended (SIGTERM, Ctrl-C); those an earlier run left when it was killed
 *    (SIGKILL: nothing runs) are removed when an output of the same name is next written, and
 *    [note] says so.
 */
/** The output name that means standard output where a command writes a stream there (`replay -o -`). */
internal const val STDOUT = "-"

internal class Outputs(
    files: FileOperations = FileOperations.SYSTEM,
    /** When this process started, ms since the epoch: only temporary files older than that can be an earlier run's. */
    private val startedMs: Long = java.lang.management.ManagementFactory.getRuntimeMXBean().startTime,
) {
    /** Where notes go (the command's standard error); set by [Cli]. */
    var note: (String) -> Unit = {}

    private val atomic = AtomicFiles(files)
    private val pending = ArrayList<AtomicFiles.PendingFile>()
    private val folders = ArrayList<Pair<Path, Path>>()
    private val direct = ArrayList<OutputStream>()
    /** The real path of each output and the name the user gave it, so that messages use the latter. */
    private val names = HashMap<String, String>()
    /** The real path of each file and folder this run writes, and the name it was given first. */
    private val claimed = HashMap<Path, String>()

    /** The output name the user gave for the real path [file], else [file]. */
    fun typed(file: String): String = names[file] ?: names[Path.of(file).toAbsolutePath().toString()] ?: file

    /**
     * A new file [output] for this run's result, checked against [inputs] (paths as given on the
     * command line). Unbuffered: wrap it in a buffer. Closing it does not move it into place.
     */
    fun file(output: String, inputs: List<String>): OutputStream {
        val target = check(output, inputs)
        if (Files.isDirectory(target)) throw FileSystemException(output, null, "is a folder; give the name of a file to write")
        if (isDevice(target)) {
            val stream = AtomicFiles.named(target) { Files.newOutputStream(target, StandardOpenOption.WRITE) }
            return NamedStream(target, stream).also { direct += it }
        }
        claim(target, output)
        removeStale(target)
        return atomic.open(target).also { pending += it }
    }

    /** Removes what a killed earlier run left beside [target], with a note. */
    private fun removeStale(target: Path) {
        val removed = AtomicFiles.removeStale(target, startedMs, ::alive)
        if (removed.isNotEmpty()) {
            note("removed ${removed.size} temporary file${if (removed.size == 1) "" else "s"} an interrupted earlier run left beside ${typed(target.toString())}: ${removed.joinToString(", ")}")
        }
    }

    /**
     * A new folder [output] (e.g. a session), filled in the returned temporary folder beside it
     * and renamed into place by [commit]; [output] must not exist or be an empty folder.
     */
    fun folder(output: String, inputs: List<String>): Path {
        val target = check(output, inputs)
        claim(target, output)
        if (Files.exists(target) && !(Files.isDirectory(target) && Files.list(target).use { !it.findAny().isPresent })) {
            throw UsageException("$output exists and is not an empty folder")
        }
        removeStale(target)
        // Listed before it is made: a signal at any moment finds it.
        val tmp = target.parent.resolve(AtomicFiles.temporaryName(target.fileName.toString(), java.lang.Long.toHexString(System.nanoTime())))
        TemporaryFiles.add(tmp)
        try {
            AtomicFiles.named(target) { Files.createDirectory(tmp) }
        } catch (e: Throwable) {
            TemporaryFiles.remove(tmp)
            throw e
        }
        folders += tmp to target
        return tmp
    }

    /** Two outputs of one run that name the same file would leave only the one moved into place last. */
    private fun claim(target: Path, output: String) {
        claimed.putIfAbsent(target, output)?.let { throw UsageException("$output and $it name the same file; give each output its own name") }
    }

    /** Moves every output into place (and syncs its folder). */
    fun commit() {
        for (d in direct) d.close()
        direct.clear()
        for (p in pending) p.commit()
        pending.clear()
        for ((tmp, target) in folders) {
            AtomicFiles.named(target) {
                if (Files.isDirectory(target, LinkOption.NOFOLLOW_LINKS)) Files.delete(target) // the empty folder it replaces
                atomic.rename(tmp, target)
                TemporaryFiles.remove(tmp)
            }
        }
        folders.clear()
    }

    /** Removes what was written aside (after a failure); never throws. */
    fun abort() {
        for (d in direct) runCatching { d.close() }
        direct.clear()
        for (p in pending) p.abort()
        pending.clear()
        for ((tmp, _) in folders) {
            runCatching { tmp.toFile().deleteRecursively() }
            if (!Files.exists(tmp, LinkOption.NOFOLLOW_LINKS)) TemporaryFiles.remove(tmp)
        }
        folders.clear()
    }

    /**
     * [output] as the name of one plain file of [what]: a name ending in '/' (a folder) or ".gz" (which
     * fusion replay compresses) would say otherwise, so it is a usage error rather than a surprise.
     */
    fun requirePlainFile(output: String, what: String) {
        if (output.endsWith("/") || output.endsWith(java.io.File.separator)) throw UsageException("$output ends in '/', but $what is one file: name the file")
        if (output.endsWith(".gz", ignoreCase = true)) throw UsageException("$output ends in .gz, but $what is written plain (as its readers take it): name it without .gz")
    }

    /**
     * The real destination of [output] (links followed, also a dangling one) after checking
     * it against [inputs].
     */
    fun check(output: String, inputs: List<String>): Path {
        if (output == STDOUT) throw UsageException("'-' (standard output) is not an output of this command here; give a file name")
        val target = destination(Path.of(output))
        names[target.toString()] = output
        for (i in inputs) {
            val input = try {
                Path.of(i).toRealPath()
            } catch (e: IOException) {
                continue // a missing input is reported when it is read; it cannot be overwritten
            }
            val same = target == input || (Files.exists(target) && Files.isSameFile(target, input))
            if (same) throw UsageException("the output $output is the input $i; write it elsewhere")
            if (target.startsWith(input)) {
                throw UsageException("the output $output lies inside the input $i; write it elsewhere")
            }
        }
        return target
    }

    private fun destination(p: Path): Path {
        var x = p.toAbsolutePath()
        var link: Path? = null
        repeat(MAX_LINKS) {
            if (isDevice(x)) return x // e.g. /dev/stdout → /proc/self/fd/1 → pipe:[…]: written as named
            if (!Files.isSymbolicLink(x)) {
                val parent = try {
                    x.parent.toRealPath()
                } catch (e: IOException) {
                    // Named as given; a dangling link also says where it points.
                    val missing = e is java.nio.file.NoSuchFileException
                    val why = when {
                        link == null && missing -> "its folder ${p.parent} does not exist; create it first"
                        link == null -> AtomicFiles.reason(e)
                        missing -> "a link to $link, whose folder does not exist"
                        else -> "a link to $link: ${AtomicFiles.reason(e)}"
                    }
                    throw FileSystemException(p.toString(), null, why).apply { initCause(e) }
                }
                return parent.resolve(x.fileName)
            }
            link = Files.readSymbolicLink(x)
            x = x.parent.resolve(link)
        }
        throw FileSystemException(p.toString(), null, "too many levels of symbolic links")
    }

    /** A device or a pipe (links followed): written directly, there is nothing to replace. */
    private fun isDevice(p: Path) = Files.exists(p) && !Files.isRegularFile(p) && !Files.isDirectory(p)

    /** A direct output (device, pipe) whose failures name the file. */
    private class NamedStream(private val target: Path, private val out: OutputStream) : OutputStream() {
        override fun write(b: Int) = AtomicFiles.named(target) { out.write(b) }
        override fun write(b: ByteArray, off: Int, len: Int) = AtomicFiles.named(target) { out.write(b, off, len) }
        override fun flush() = AtomicFiles.named(target) { out.flush() }
        override fun close() = AtomicFiles.named(target) { out.close() }
    }

    companion object {
        private const val MAX_LINKS = 40

        /** True when the process [owner] (a process id) of a temporary name may still be running. */
        fun alive(owner: String): Boolean = owner.toLongOrNull()?.let { pid -> ProcessHandle.of(pid).map { it.isAlive }.orElse(false) } ?: true
    }
}

/** Standard output failed (closed pipe, full device); the message is the reason. */
internal class StdoutException(reason: String) : IOException(reason)

/**
 * Standard output that stops the run once it fails (e.g. `fusion replay … | head`):
 * PrintStream swallows write errors, which would let a long replay run on for nothing.
 */
internal class StdoutGuard(private val out: PrintStream) : OutputStream() {
    override fun write(b: Int) = write(byteArrayOf(b.toByte()), 0, 1)

    override fun write(b: ByteArray, off: Int, len: Int) {
        out.write(b, off, len)
        if (out.checkError()) throw StdoutException("write failed")
    }

    override fun flush() {
        out.flush()
        if (out.checkError()) throw StdoutException("write failed")
    }
}

/** The process's standard output, remembering why a write failed (PrintStream only says that one did). */
internal class RecordingOutput(private val out: OutputStream) : OutputStream() {
    @Volatile
    var failure: IOException? = null
        private set

    override fun write(b: Int) = guard { out.write(b) }
    override fun write(b: ByteArray, off: Int, len: Int) = guard { out.write(b, off, len) }
    override fun flush() = guard { out.flush() }
    override fun close() = guard { out.close() }

    private inline fun guard(block: () -> Unit) {
        try {
            block()
        } catch (e: IOException) {
            if (failure == null) failure = e
            throw e
        }
    }
}
