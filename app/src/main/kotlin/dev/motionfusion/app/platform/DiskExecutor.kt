package dev.motionfusion.app.platform

import android.os.Looper
import android.os.StrictMode
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
        /** Disk work on the main thread is a bug (an ANR on a slow card): fail loudly, in tests too ([MainThreadPolicy]). */
        fun checkNotMainThread() = MainThreadPolicy.checkNotMainThread()
    }
}

/**
 * The app's one rule against disk and network work on the main thread. Android's StrictMode
 * watches the framework's own disk and network calls (SharedPreferences, the folder that
 * `getFilesDir()` creates, SQLite, sockets) once [install]ed: debug builds log them, and every
 * Robolectric test installs it with [fail], so a test whose main thread touches the disk fails
 * at that call. The app's own file work (java.io/java.nio) is invisible to StrictMode on a JVM,
 * so every path into it (the disk executor's folder locks, [AppFiles], the settings and
 * calibration stores) calls [checkNotMainThread], which throws.
 */
object MainThreadPolicy {
    /**
     * Turns StrictMode on for the calling (main) thread: disk reads, disk writes and network.
     * [fail]: the offending call throws (penaltyDeath alone: StrictMode then reports at the call,
     * not later from the looper), else the violation is logged.
     */
    fun install(fail: Boolean) {
        val policy = StrictMode.ThreadPolicy.Builder().detectDiskReads().detectDiskWrites().detectNetwork()
        StrictMode.setThreadPolicy((if (fail) policy.penaltyDeath() else policy.penaltyLog()).build())
    }

    /** Throws on the main thread: the app's own disk work must go through the disk executor. */
    fun checkNotMainThread() {
        check(Looper.myLooper() != Looper.getMainLooper() || Looper.getMainLooper() == null) {
            "disk work on the main thread"
        }
    }
}

/**
 * The app's private files folder, `Context.getFilesDir()`, resolved on first use, off the main
 * thread only: the framework creates the folder on its first call (a disk write). The object
 * graph is built on the main thread with this handle; the disk executor resolves it.
 */
class AppFiles(resolve: () -> File) {
    private val root by lazy(resolve)

    /** The folder [name] inside it (not created). Off the main thread. */
    fun folder(name: String): File {
        MainThreadPolicy.checkNotMainThread()
        return File(root, name)
    }
}

/**
 * A disk queue: one background thread named [name], tasks in order, each under its folder's lock.
 * The app has two (AppGraph): the recording's own (preparing, resuming and ending a recording, never
 * behind anything else) and the screens' (reads, exports, shares, rename, delete); they share the
 * folder locks, so the two never work on one session folder at once.
 */
class SerialDiskExecutor(private val locks: FolderLocks = FolderLocks(), name: String = "disk") : DiskExecutor {
    private val executor: ExecutorService = Executors.newSingleThreadExecutor { r -> Thread(r, name).apply { isDaemon = true } }

    override fun execute(folder: File?, task: () -> Unit) {
        executor.execute { locks.withFolder(folder, task) }
    }
}
