package dev.motionfusion.app.platform

import android.os.Looper
import java.io.File
import java.util.concurrent.ConcurrentHashMap
import java.util.concurrent.ExecutorService
import java.util.concurrent.Executors
import java.util.concurrent.locks.ReentrantLock
import kotlin.concurrent.withLock

/**
 * Where the app's disk work runs: never on the main thread. Each task names the session folder
 * it works on (or none); tasks on one folder never run at once (repair, export, delete and
 * rename of a folder are serialised by the folder's lock, whatever thread runs them).
 */
interface DiskExecutor {
    /** Runs [task] off the main thread, holding [folder]'s lock when given. */
    fun execute(folder: File?, task: () -> Unit)
}

/** The folder locks, by canonical path. */
class FolderLocks {
    private val locks = ConcurrentHashMap<String, ReentrantLock>()

    /** Runs [block] holding [folder]'s lock; refuses to run on the main thread. */
    fun <T> withFolder(folder: File?, block: () -> T): T {
        checkNotMainThread()
        if (folder == null) return block()
        val lock = locks.computeIfAbsent(folder.absoluteFile.normalize().path) { ReentrantLock() }
        return lock.withLock(block)
    }

    companion object {
        /** Disk work on the main thread is a bug (an ANR on a slow card): fail loudly, in tests too. */
        fun checkNotMainThread() {
            check(Looper.myLooper() != Looper.getMainLooper() || Looper.getMainLooper() == null) {
                "disk work on the main thread"
            }
        }
    }
}

/** The app's disk executor: one background thread, tasks in order, each under its folder's lock. */
class SerialDiskExecutor(private val locks: FolderLocks = FolderLocks()) : DiskExecutor {
    private val executor: ExecutorService = Executors.newSingleThreadExecutor { r -> Thread(r, "disk").apply { isDaemon = true } }

    override fun execute(folder: File?, task: () -> Unit) {
        executor.execute { locks.withFolder(folder, task) }
    }
}
