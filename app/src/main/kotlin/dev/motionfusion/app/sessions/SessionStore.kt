package dev.motionfusion.app.sessions

import dev.motionfusion.app.platform.InvalidSessionNameException
import dev.motionfusion.app.platform.SessionBusyException
import dev.motionfusion.core.io.AtomicFiles
import java.io.File
import java.io.IOException

/** Rename and delete of session folders (app-private storage), refusing the one being recorded. Disk executor only. */
internal object SessionStore {
    private val validName = Regex("[A-Za-z0-9][A-Za-z0-9 ._-]{0,79}")

    /** A name that can become a folder and a zip name on any platform. */
    fun isValidName(name: String): Boolean = validName.matches(name) && !name.endsWith(".") && !name.endsWith(" ")

    /** Renames [dir] to [newName] beside it; returns the new folder. */
    @Throws(IOException::class)
    fun rename(sessions: SessionsRepository, dir: File, newName: String): File {
        val name = newName.trim()
        if (!isValidName(name)) throw InvalidSessionNameException("invalid name")
        if (sessions.isRecording(dir)) throw SessionBusyException("the session is being recorded")
        val target = File(dir.parentFile, name)
        if (target.exists()) throw InvalidSessionNameException("a session called $name exists")
        AtomicFiles().rename(dir.toPath(), target.toPath()) // one atomic step, then the folder synced
        return target
    }

    @Throws(IOException::class)
    fun delete(sessions: SessionsRepository, dir: File) {
        if (sessions.isRecording(dir)) throw SessionBusyException("the session is being recorded")
        if (!dir.deleteRecursively()) throw IOException("cannot delete ${dir.name}")
    }

    /** Bytes of all files under [dir]. */
    fun sizeOf(dir: File): Long = dir.walkTopDown().filter { it.isFile }.sumOf { it.length() }
}
