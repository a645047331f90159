package dev.motionfusion.core.io

import java.io.IOException
import java.nio.file.Path

/** The process dies here. An Error, not an IOException: no code path of the project handles it, as none survives a kill. */
internal class SimulatedKill : Error("simulated kill")

/**
 * [FileOperations] on the real file system with two faults, for failure injection without root:
 *  - storage full: once [spaceBytes] bytes have been written in all, a write stores what still
 *    fits and fails with "No space left on device" (as write(2) on a full disk);
 *  - a kill at step [killAt] (0-based count of create, write, sync, truncate, move, syncFolder,
 *    delete): a write killed there stores half its bytes first (a partial row); from then on
 *    every call dies too. [closeAll] then closes the files, as the OS does for a dead process.
 * [steps] counts the steps taken, so a run without faults tells how many kill points there are.
 */
internal class FaultyFiles(
    private val spaceBytes: Long = Long.MAX_VALUE,
    private val killAt: Int = Int.MAX_VALUE,
    private val real: FileOperations = FileOperations.SYSTEM,
) : FileOperations {
    var steps = 0
        private set
    var written = 0L
        private set
    var killed = false
        private set
    private val open = ArrayList<SyncedOutput>()

    /** Counts a step; true when the process dies at it. */
    private fun step(): Boolean {
        if (killed) throw SimulatedKill()
        return steps++ == killAt
    }

    private fun die(): Nothing {
        killed = true
        throw SimulatedKill()
    }

    override fun create(path: Path): SyncedOutput = faulty(real.create(path))

    override fun open(path: Path): SyncedOutput = faulty(real.open(path))

    private fun faulty(opened: SyncedOutput): SyncedOutput {
        if (step()) {
            opened.close()
            die()
        }
        val out = opened
        open += out
        return object : SyncedOutput() {
            override fun write(b: Int) = write(byteArrayOf(b.toByte()), 0, 1)

            override fun write(b: ByteArray, off: Int, len: Int) {
                val dies = step()
                val n = if (dies) len / 2 else minOf(len.toLong(), maxOf(0L, spaceBytes - written)).toInt()
                if (n > 0) out.write(b, off, n)
                written += n
                if (dies) die()
                if (n < len) throw IOException("No space left on device")
            }

            override fun sync() {
                if (step()) die()
                out.sync()
            }

            override fun close() = out.close()
        }
    }

    override fun truncate(path: Path, size: Long) {
        if (step()) die()
        real.truncate(path, size)
    }

    override fun move(source: Path, target: Path, replace: Boolean) {
        if (step()) die()
        real.move(source, target, replace)
    }

    override fun syncFolder(dir: Path) {
        if (step()) die()
        real.syncFolder(dir)
    }

    override fun delete(path: Path) {
        if (step()) die()
        real.delete(path)
    }

    fun closeAll() {
        for (o in open) runCatching { o.close() }
        open.clear()
    }
}
