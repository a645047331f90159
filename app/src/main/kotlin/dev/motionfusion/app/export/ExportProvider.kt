package dev.motionfusion.app.export

import android.content.ContentProvider
import android.content.ContentValues
import android.content.Context
import android.database.Cursor
import android.database.MatrixCursor
import android.net.Uri
import android.os.ParcelFileDescriptor
import android.provider.OpenableColumns
import java.io.File
import java.io.FileNotFoundException

/**
 * Serves exported sessions (zips, MCAP and gcsv files) to the app another app was asked to share with: read-only,
 * `content://<package>.export/<file>` for files in `cacheDir/exports/` and nothing else.
 * Not exported; readable only through a `FLAG_GRANT_READ_URI_PERMISSION` grant on the share
 * intent (the manifest sets `grantUriPermissions`). The framework's answer to AndroidX's
 * FileProvider for this one folder.
 */
class ExportProvider : ContentProvider() {
    override fun onCreate(): Boolean = true

    private fun fileOf(uri: Uri): File {
        val ctx = context ?: throw FileNotFoundException("no context")
        val name = uri.lastPathSegment ?: throw FileNotFoundException("$uri")
        val dir = exportDir(ctx).canonicalFile
        val f = File(dir, name).canonicalFile
        if (uri.pathSegments.size != 1 || f.parentFile != dir || !f.isFile) throw FileNotFoundException("$uri")
        return f
    }

    override fun openFile(uri: Uri, mode: String): ParcelFileDescriptor {
        if (mode != "r") throw SecurityException("read-only")
        return ParcelFileDescriptor.open(fileOf(uri), ParcelFileDescriptor.MODE_READ_ONLY)
    }

    override fun query(uri: Uri, projection: Array<out String>?, selection: String?, selectionArgs: Array<out String>?, sortOrder: String?): Cursor {
        val f = fileOf(uri)
        val columns = projection?.filter { it == OpenableColumns.DISPLAY_NAME || it == OpenableColumns.SIZE }?.toTypedArray()
            ?: arrayOf(OpenableColumns.DISPLAY_NAME, OpenableColumns.SIZE)
        return MatrixCursor(columns, 1).apply {
            addRow(columns.map { if (it == OpenableColumns.DISPLAY_NAME) f.name else f.length() })
        }
    }

    override fun getType(uri: Uri): String {
        val name = uri.lastPathSegment ?: return MIME_ZIP
        return ExportKind.entries.filter { name.endsWith(it.suffix) }.maxByOrNull { it.suffix.length }?.mime ?: MIME_ZIP
    }

    override fun insert(uri: Uri, values: ContentValues?): Uri? = throw UnsupportedOperationException("read-only")

    override fun delete(uri: Uri, selection: String?, selectionArgs: Array<out String>?): Int = throw UnsupportedOperationException("read-only")

    override fun update(uri: Uri, values: ContentValues?, selection: String?, selectionArgs: Array<out String>?): Int =
        throw UnsupportedOperationException("read-only")

    internal companion object {
        const val MIME_ZIP = "application/zip"
        const val MIME_BINARY = "application/octet-stream"
        const val MIME_TEXT = "text/csv"

        fun authority(context: Context) = "${context.packageName}.export"

        fun exportDir(context: Context) = File(context.cacheDir, "exports")

        fun uriFor(context: Context, file: File): Uri =
            Uri.Builder().scheme("content").authority(authority(context)).appendPath(file.name).build()
    }
}
