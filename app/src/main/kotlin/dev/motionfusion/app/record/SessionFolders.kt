package dev.motionfusion.app.record

import android.content.Context
import java.io.File
import java.text.SimpleDateFormat
import java.util.Date
import java.util.Locale
import java.util.TimeZone

/** Where sessions live: app-private storage (`filesDir/sessions/<name>/`), until exported. */
internal object SessionFolders {
    fun root(context: Context): File = File(context.filesDir, "sessions").apply { mkdirs() }

    /** A new, not yet existing folder named after the UTC start time, e.g. `2026-11-26_13-05-00`. */
    fun newSession(context: Context, wallClockMs: Long): File {
        val f = SimpleDateFormat("yyyy-MM-dd_HH-mm-ss", Locale.ROOT).apply { timeZone = TimeZone.getTimeZone("UTC") }
        val base = "session_" + f.format(Date(wallClockMs))
        val root = root(context)
        var dir = File(root, base)
        var i = 2
        while (dir.exists()) dir = File(root, "${base}_${i++}")
        return dir
    }

    /** Session folders, newest first by name. */
    fun list(context: Context): List<File> =
        root(context).listFiles { f -> f.isDirectory }?.sortedByDescending { it.name } ?: emptyList()
}
