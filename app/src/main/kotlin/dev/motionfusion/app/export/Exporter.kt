package dev.motionfusion.app.export

import dev.motionfusion.app.platform.SessionBusyException
import dev.motionfusion.app.platform.UnreadableSessionException
import android.content.ClipData
import android.content.ContentValues
import android.content.Context
import android.content.Intent
import android.net.Uri
import android.os.Build
import androidx.annotation.RequiresApi
import android.os.Environment
import android.provider.DocumentsContract
import android.provider.MediaStore
import kotlinx.coroutines.CancellationException
import dev.motionfusion.app.R
import dev.motionfusion.core.io.AtomicFiles
import dev.motionfusion.core.session.SessionArchive
import dev.motionfusion.core.session.SessionReader
import java.io.File
import java.io.IOException

/**
 * The three ways a session leaves app-private storage, each as one zip of the session format
 * ([SessionArchive.zip]: the folder's files inside a folder named after the session):
 * Downloads through MediaStore (API 29+, no permission), a document the user picks
 * (ACTION_CREATE_DOCUMENT), and a share sheet with a content:// URI from [ExportProvider].
 * Blocking: call off the main thread. [Progress] gets the bytes of the session read so far and
 * their total; an exception it throws (a cancelled export's) stops the export, and what was begun
 * is removed (the zip aside, the pending Downloads entry, the picked document).
 */
internal object Exporter {
    /** How far an export is: (bytes of the session's files read, their total). */
    fun interface Progress {
        fun update(done: Long, total: Long)
    }

    private val NONE = Progress { _, _ -> }

    fun zipName(session: String): String = "$session.zip"

    /** Only a finished (or repaired) session leaves the app: never one being written. */
    @Throws(IOException::class)
    fun checkExportable(dir: File) {
        val complete = try {
            SessionReader.open(dir.toPath()).use { it.metadata.complete }
        } catch (e: Exception) {
            throw UnreadableSessionException("${dir.name} is not a readable session: ${e.message}", e)
        }
        if (!complete) throw SessionBusyException("${dir.name} is still being recorded")
    }

    /** Writes the zip to [target] all-or-nothing (the project's [AtomicFiles]): a failed export leaves no partial zip. */
    @Throws(IOException::class)
    fun writeZip(dir: File, target: File, progress: Progress = NONE) {
        checkExportable(dir)
        target.parentFile?.mkdirs()
        AtomicFiles().write(target.toPath()) { SessionArchive.zip(dir.toPath(), it, null, progress::update) }
    }

    /** MediaStore.Downloads needs API 29; before that, Save as… covers it without a storage permission. */
    val downloadsAvailable: Boolean get() = Build.VERSION.SDK_INT >= 29

    /** Saves to Downloads: inserted pending, written, then published. Returns the display name. */
    @RequiresApi(29)
    @Throws(IOException::class)
    fun toDownloads(context: Context, dir: File, progress: Progress = NONE): String {
        check(downloadsAvailable) { "MediaStore.Downloads needs API 29" }
        checkExportable(dir)
        val resolver = context.contentResolver
        val name = zipName(dir.name)
        val values = ContentValues().apply {
            put(MediaStore.MediaColumns.DISPLAY_NAME, name)
            put(MediaStore.MediaColumns.MIME_TYPE, ExportProvider.MIME_ZIP)
            put(MediaStore.MediaColumns.RELATIVE_PATH, Environment.DIRECTORY_DOWNLOADS)
            put(MediaStore.MediaColumns.IS_PENDING, 1)
        }
        val uri = resolver.insert(MediaStore.Downloads.EXTERNAL_CONTENT_URI, values)
            ?: throw IOException("Downloads refused the file")
        try {
            resolver.openOutputStream(uri, "w")?.use { SessionArchive.zip(dir.toPath(), it, null, progress::update) } ?: throw IOException("cannot open $name")
            resolver.update(uri, ContentValues().apply { put(MediaStore.MediaColumns.IS_PENDING, 0) }, null, null)
        } catch (e: Exception) {
            resolver.delete(uri, null, null)
            if (e is IOException || e is CancellationException) throw e
            throw IOException(e.message, e)
        }
        return name
    }

    /** The intent that asks the user where to save the zip (result: a document URI for [toDocument]). */

    /** Writes the zip into the document the user created. */
    @Throws(IOException::class)
    fun toDocument(context: Context, dir: File, document: Uri, progress: Progress = NONE) {
        checkExportable(dir)
        try {
            context.contentResolver.openOutputStream(document, "wt")?.use { SessionArchive.zip(dir.toPath(), it, null, progress::update) }
                ?: throw IOException("cannot open the document")
        } catch (e: Exception) {
            // The document the picker created holds a part of a zip: removed when its provider allows.
            runCatching { DocumentsContract.deleteDocument(context.contentResolver, document) }
            throw e
        }
    }

    /** Zips into the provider's folder and returns a chooser for ACTION_SEND with a read grant. */
    @Throws(IOException::class)
    fun shareIntent(context: Context, dir: File, progress: Progress = NONE): Intent {
        val exports = ExportProvider.exportDir(context)
        // The cache is for handing over, not for keeping: zips shared a day ago are gone.
        val dayAgo = System.currentTimeMillis() - 24L * 3600 * 1000
        exports.listFiles()?.filter { it.lastModified() < dayAgo }?.forEach { it.delete() }
        val zip = File(exports, zipName(dir.name))
        writeZip(dir, zip, progress)
        val uri = ExportProvider.uriFor(context, zip)
        val send = Intent(Intent.ACTION_SEND)
            .setType(ExportProvider.MIME_ZIP)
            .putExtra(Intent.EXTRA_STREAM, uri)
            .putExtra(Intent.EXTRA_SUBJECT, dir.name)
            .addFlags(Intent.FLAG_GRANT_READ_URI_PERMISSION)
        send.clipData = ClipData.newRawUri(dir.name, uri)
        return Intent.createChooser(send, context.getString(R.string.export_share_title))
            .addFlags(Intent.FLAG_GRANT_READ_URI_PERMISSION)
    }
}
